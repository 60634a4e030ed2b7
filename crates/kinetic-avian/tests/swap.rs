//! The plugin against avian's own broad phase, headless: the same contacts on kinematic
//! scenes, no pair missed on dynamic ones, fast bodies, sleeping, removed and disabled
//! colliders, collision layers.

mod common;

use avian3d::prelude::*;
use bevy::prelude::*;
use common::*;
use kinetic_avian::KineticBroadPhasePlugin;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Kinematic balls and boxes flying and spinning through a field of static boxes.
fn kinematic_scene(app: &mut App, seed: u64, n: usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut r = |lo: f32, hi: f32| rng.random_range(lo..hi);
    for _ in 0..n / 8 {
        let at = Vec3::new(r(-12.0, 12.0), r(-12.0, 12.0), r(-12.0, 12.0));
        let size = Vec3::new(r(0.5, 3.0), r(0.5, 3.0), r(0.5, 3.0));
        spawn(
            app,
            (
                RigidBody::Static,
                Collider::cuboid(size.x, size.y, size.z),
                Transform::from_translation(at),
            ),
        );
    }
    for k in 0..n {
        let at = Vec3::new(r(-12.0, 12.0), r(-12.0, 12.0), r(-12.0, 12.0));
        let v = Vec3::new(r(-4.0, 4.0), r(-4.0, 4.0), r(-4.0, 4.0));
        let w = Vec3::new(r(-2.0, 2.0), r(-2.0, 2.0), r(-2.0, 2.0));
        let collider = if k % 2 == 0 {
            Collider::sphere(r(0.2, 0.8))
        } else {
            Collider::cuboid(r(0.3, 1.5), r(0.3, 1.5), r(0.3, 1.5))
        };
        spawn(
            app,
            (
                RigidBody::Kinematic,
                collider,
                Transform::from_translation(at),
                LinearVelocity(v),
                AngularVelocity(w),
            ),
        );
    }
}

#[test]
fn kinematic_bodies_touch_as_with_avians_broad_phase() {
    // The plugin as it comes (a crowd flying through each other steps) and held to the loose
    // grid (kinetic throughout).
    let kinetic_loose = Broad::LooseGrid(true);
    for (seed, broad) in [(1, Broad::Kinetic), (2, Broad::Kinetic), (1, kinetic_loose)] {
        let (mut ours, mut theirs) = (app(broad), app(Broad::Default));
        kinematic_scene(&mut ours, seed, 120);
        kinematic_scene(&mut theirs, seed, 120);
        let mut seen = 0;
        for k in 0..200 {
            step(&mut ours);
            step(&mut theirs);
            let (a, b) = (touching(&ours), touching(&theirs));
            assert_eq!(a, b, "seed {seed}, step {k}");
            seen += a.len();
        }
        assert!(seen > 200, "seed {seed}: only {seen} touching pairs seen");
        if broad == kinetic_loose {
            assert!(kinetic(&ours).stats().events > 0);
        }
    }
}

/// A draw of the engine scene space: columns of boxes, most asleep, a few bodies dropped and
/// fast ones flying through. The broad phase steps, looks up the moving boxes each step in
/// avian's own collider trees, and misses no pair.
#[test]
fn a_mostly_sleeping_stack_looks_up_its_moving_boxes_in_avians_trees_and_misses_no_pair() {
    let draw = kinetic_scenes::engines::space::draw(13);
    let mut ours = app(Broad::Kinetic);
    let entities = kinetic_scenes::avian::spawn(&draw.scene, ours.world_mut());
    // The first update sets the clocks; the second steps, making the islands to sleep in.
    step(&mut ours);
    step(&mut ours);
    kinetic_scenes::avian::put_to_sleep(&draw.scene, ours.world_mut(), &entities);
    for k in 0..15 {
        let missing = step_missing(&mut ours, 0.01);
        assert!(missing.is_empty(), "step {k}: {missing:?}");
    }
    let stats = kinetic(&ours).stats();
    assert!(stats.engine_lookups > 0 && stats.added > 0, "{stats:?}");
    assert_eq!(kinetic(&ours).structure_name(), "stepped");
}

/// Runs `steps` steps, asserting after each that no pair within 0.01 is missing from the
/// contact graph (`what` names the run); returns the touching pairs seen, summed over steps.
fn steps_missing_none(app: &mut App, steps: usize, what: &str) -> usize {
    let mut touching_seen = 0;
    for k in 0..steps {
        let missing = step_missing(app, 0.01);
        assert!(missing.is_empty(), "{what}, step {k}: {missing:?}");
        touching_seen += touching(app).len();
    }
    touching_seen
}

/// Every rigid body, in the world's order.
fn bodies(world: &mut World) -> Vec<Entity> {
    let mut q = world.query_filtered::<Entity, With<RigidBody>>();
    q.iter(world).collect()
}

/// Balls and boxes dropped in layers onto a ground.
fn rain(app: &mut App, seed: u64, n: usize) {
    ground(app);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for k in 0..n {
        let at = Vec3::new(
            rng.random_range(-5.0..5.0),
            1.0 + k as f32 * 0.15,
            rng.random_range(-5.0..5.0),
        );
        if k % 3 == 0 {
            spawn(app, cuboid(at, Vec3::splat(rng.random_range(0.4..1.0))));
        } else {
            spawn(app, ball(at, rng.random_range(0.2..0.5)));
        }
    }
}

#[test]
fn a_rain_onto_the_ground_misses_no_pair_within_reach() {
    // The broad phase's own pick (stepped, on avian's enlarged boxes) and the kinetic
    // structure the caller chose.
    for broad in [Broad::Kinetic, Broad::LooseGrid(false)] {
        let mut ours = app(broad);
        rain(&mut ours, 7, 150);
        let touching_seen = steps_missing_none(&mut ours, 240, &format!("{broad:?}"));
        assert!(touching_seen > 1000, "{touching_seen}");
        // The pile came to rest on the ground: nothing fell through.
        let mut q = ours.world_mut().query::<(&Position, &RigidBody)>();
        let lowest = q
            .iter(ours.world())
            .filter(|(_, rb)| rb.is_dynamic())
            .map(|(p, _)| p.0.y as f64)
            .fold(f64::INFINITY, f64::min);
        assert!(lowest > 0.1, "a body at {lowest}");
        let (name, stats) = (kinetic(&ours).structure_name(), kinetic(&ours).stats());
        if broad == Broad::Kinetic {
            // avian keeps enlarged boxes: the world steps on them for good.
            assert_eq!((name, stats.switches), ("stepped", 0), "{stats:?}");
        } else {
            assert_eq!(name, "grid");
            assert!(stats.replans > 0, "{stats:?}");
        }
    }
}

#[test]
fn bodies_added_after_the_ground_has_stepped_alone_miss_no_pair() {
    // The broad phase's first colliders are the ground's: it still steps on avian's
    // enlarged boxes once the bodies come.
    let mut ours = app(Broad::Kinetic);
    ground(&mut ours);
    for _ in 0..3 {
        step(&mut ours);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for k in 0..80 {
        let at = Vec3::new(
            rng.random_range(-3.0..3.0),
            1.0 + k as f32 * 0.2,
            rng.random_range(-3.0..3.0),
        );
        spawn(&mut ours, ball(at, rng.random_range(0.2..0.4)));
    }
    let touching_seen = steps_missing_none(&mut ours, 150, "kinetic");
    assert!(touching_seen > 500, "{touching_seen}");
    let (name, stats) = (kinetic(&ours).structure_name(), kinetic(&ours).stats());
    assert_eq!((name, stats.switches), ("stepped", 0), "{stats:?}");
    assert_eq!(audit(&ours), None);
}

#[test]
fn a_fast_ball_does_not_skip_a_thin_walls_pair() {
    for ccd in [false, true] {
        let mut ours = app(Broad::Kinetic);
        let wall = spawn(
            &mut ours,
            (
                RigidBody::Static,
                Collider::cuboid(0.1, 10.0, 10.0),
                Transform::from_xyz(20.0, 0.0, 0.0),
            ),
        );
        // 300 m/s: about 4.7 m a step, the wall 0.1 thick.
        let shot = spawn(
            &mut ours,
            (
                RigidBody::Dynamic,
                Collider::sphere(0.25),
                Transform::from_xyz(0.0, 0.0, 0.0),
                LinearVelocity(Vec3::new(300.0, 0.0, 0.0)),
                GravityScale(0.0),
            ),
        );
        if ccd {
            ours.world_mut()
                .entity_mut(shot)
                .insert(SpeculativeCcd::MAX);
        }
        let mut live = false;
        for _ in 0..10 {
            step(&mut ours);
            live |= kinetic(&ours).is_live(wall, shot);
        }
        // The broad phase sees the pair in the step the ball crosses, boxes or no boxes.
        assert!(live, "ccd {ccd}: the wall's pair was never live");
        let x = position(&ours, shot).x;
        if ccd {
            // With speculative contacts on, the pair reaches the solver: the ball stops.
            assert!(x < 20.0, "the ball went through, to {x}");
        }
    }
}

#[test]
fn sleeping_bodies_cost_nothing_until_woken() {
    let mut ours = app(Broad::Kinetic);
    ground(&mut ours);
    let mut boxes = Vec::new();
    for i in 0..10 {
        for j in 0..10 {
            let at = Vec3::new(i as f32 * 1.5 - 7.0, 0.5, j as f32 * 1.5 - 7.0);
            boxes.push(spawn(&mut ours, cuboid(at, Vec3::ONE)));
        }
    }
    // Settle and fall asleep.
    for _ in 0..300 {
        step(&mut ours);
    }
    let asleep = boxes
        .iter()
        .filter(|&&b| ours.world().get::<Sleeping>(b).is_some())
        .count();
    assert!(asleep >= 90, "{asleep} of 100 asleep");
    let before = kinetic(&ours).stats();
    for _ in 0..30 {
        step(&mut ours);
        assert_eq!(kinetic(&ours).last_step().events, 0);
    }
    let after = kinetic(&ours).stats();
    assert_eq!(after.replans, before.replans, "sleeping bodies re-planned");
    assert_eq!(after.inserts, before.inserts);
    // A ball dropped onto one wakes it, and the pair is made.
    let target = boxes[44];
    let top = position(&ours, target) + Vec3::new(0.0, 3.0, 0.0);
    let dropped = spawn(&mut ours, ball(top, 0.3));
    let mut met = false;
    for _ in 0..90 {
        step(&mut ours);
        met |= touching(&ours).contains(&tags(&ours, target, dropped));
    }
    assert!(met, "the dropped ball never touched the box");
    assert!(step_missing(&mut ours, 0.0).is_empty());
}

#[test]
fn colliders_come_and_go_and_are_disabled() {
    for broad in [Broad::Default, Broad::Kinetic] {
        come_and_go(broad);
    }
}

fn come_and_go(broad: Broad) {
    let mut ours = app(broad);
    rain(&mut ours, 3, 60);
    let bodies = bodies(ours.world_mut());
    for k in 0..180 {
        let missing = step_missing(&mut ours, 0.0);
        // A collider enabled again has its box refreshed during its first step back: avian's
        // own broad phase, like this one, hands its pairs over a step later.
        if k != 121 {
            assert!(missing.is_empty(), "{broad:?}, step {k}: {missing:?}");
        }
        if k == 40 {
            // Remove a third of the bodies, spawn new ones (which may take their indices).
            for &b in bodies.iter().skip(1).step_by(3) {
                ours.world_mut().despawn(b);
            }
            for i in 0..20 {
                spawn(
                    &mut ours,
                    ball(Vec3::new(i as f32 * 0.5 - 5.0, 6.0, 0.0), 0.3),
                );
            }
        }
        if k == 80 {
            for &b in bodies.iter().skip(2).step_by(3) {
                ours.world_mut().entity_mut(b).insert(ColliderDisabled);
            }
        }
        if k == 120 {
            for &b in bodies.iter().skip(2).step_by(3) {
                ours.world_mut().entity_mut(b).remove::<ColliderDisabled>();
            }
        }
    }
    if broad == Broad::Kinetic {
        let held = kinetic(&ours).core().held();
        let colliders = {
            let mut q = ours.world_mut().query_filtered::<Entity, With<Collider>>();
            q.iter(ours.world()).count()
        };
        assert_eq!(held, colliders);
    }
}

#[test]
fn collision_layers_keep_pairs_apart_as_with_avians_broad_phase() {
    for broad in [Broad::Kinetic, Broad::Default] {
        let mut app = app(broad);
        ground(&mut app);
        // Two balls dropped onto one spot, on layers that interact with the ground's (the
        // first) but not with each other: they pass through each other onto the ground.
        let a = spawn(
            &mut app,
            (
                ball(Vec3::new(0.0, 1.0, 0.0), 0.5),
                CollisionLayers::from_bits(0b10, 0b01),
            ),
        );
        let b = spawn(
            &mut app,
            (
                ball(Vec3::new(0.0, 2.5, 0.0), 0.5),
                CollisionLayers::from_bits(0b100, 0b01),
            ),
        );
        for _ in 0..120 {
            step(&mut app);
        }
        let (ya, yb) = (position(&app, a).y, position(&app, b).y);
        assert!(
            (ya - 0.5).abs() < 0.05 && (yb - 0.5).abs() < 0.05,
            "{broad:?}: {ya} {yb}"
        );
        assert!(!touching(&app).contains(&tags(&app, a, b)), "{broad:?}");
        assert_eq!(touching(&app).len(), 2, "{broad:?}: {:?}", touching(&app));
    }
}

/// Colliders marked `Ghost` pass through each other (a `filter_pairs` hook).
#[derive(Component)]
struct Ghost;

#[derive(bevy::ecs::system::SystemParam)]
struct GhostHooks<'w, 's> {
    ghosts: Query<'w, 's, (), With<Ghost>>,
}

impl CollisionHooks for GhostHooks<'_, '_> {
    fn filter_pairs(&self, a: Entity, b: Entity, _: &mut Commands) -> bool {
        !(self.ghosts.contains(a) && self.ghosts.contains(b))
    }
}

/// A headless app with the ghost hooks, and either broad phase.
fn app_with_hooks(broad: Broad) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    let physics = PhysicsPlugins::default()
        .with_collision_hooks::<GhostHooks>()
        .build();
    match broad {
        Broad::Default => app.add_plugins(physics),
        Broad::Kinetic => app.add_plugins(
            physics
                .disable::<BvhBroadPhasePlugin<GhostHooks>>()
                .add(KineticBroadPhasePlugin::<GhostHooks>::default().with_audit()),
        ),
        Broad::LooseGrid(loose) => app.add_plugins(
            physics.disable::<BvhBroadPhasePlugin<GhostHooks>>().add(
                KineticBroadPhasePlugin::<GhostHooks>::default()
                    .with_loose_grid(loose)
                    .with_audit(),
            ),
        ),
    };
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(
        std::time::Duration::from_secs_f64(1.0 / HZ),
    ));
    app.finish();
    app
}

#[test]
fn joints_and_the_filter_hook_keep_pairs_apart_as_with_avians_broad_phase() {
    for broad in [Broad::Default, Broad::Kinetic] {
        let mut app = app_with_hooks(broad);
        ground(&mut app);
        // Two balls overlapping, joined with collisions disabled; two ghosts overlapping; a
        // ghost and a plain ball overlapping.
        let a = spawn(&mut app, ball(Vec3::new(-6.0, 0.5, 0.0), 0.5));
        let b = spawn(&mut app, ball(Vec3::new(-5.4, 0.5, 0.0), 0.5));
        app.world_mut()
            .spawn((DistanceJoint::new(a, b), JointCollisionDisabled));
        let hooks = ActiveCollisionHooks::FILTER_PAIRS;
        let g1 = spawn(
            &mut app,
            (ball(Vec3::new(0.0, 0.5, 0.0), 0.5), Ghost, hooks),
        );
        let g2 = spawn(
            &mut app,
            (ball(Vec3::new(0.6, 0.5, 0.0), 0.5), Ghost, hooks),
        );
        let plain = spawn(&mut app, (ball(Vec3::new(6.0, 0.5, 0.0), 0.5), hooks));
        let g3 = spawn(
            &mut app,
            (ball(Vec3::new(6.6, 0.5, 0.0), 0.5), Ghost, hooks),
        );
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..30 {
            step(&mut app);
            seen.extend(touching(&app));
        }
        assert!(!seen.contains(&tags(&app, a, b)), "{broad:?}: jointed pair");
        assert!(!seen.contains(&tags(&app, g1, g2)), "{broad:?}: ghosts");
        assert!(
            seen.contains(&tags(&app, plain, g3)),
            "{broad:?}: a ghost and a ball"
        );
    }
}

#[test]
fn layers_and_body_types_changed_midway_miss_no_pair() {
    for broad in [Broad::Kinetic, Broad::LooseGrid(true)] {
        changed_midway(broad);
    }
}

fn changed_midway(broad: Broad) {
    let mut app = app(broad);
    rain(&mut app, 5, 60);
    let bodies = bodies(app.world_mut());
    let apart = CollisionLayers::from_bits(0b10, 0b01);
    for k in 0..160 {
        let missing = step_missing(&mut app, 0.0);
        assert!(missing.is_empty(), "{broad:?}, step {k}: {missing:?}");
        match k {
            // Every other body on a layer that meets only the ground, then back.
            30 => bodies.iter().step_by(2).for_each(|&b| {
                app.world_mut().entity_mut(b).insert(apart);
            }),
            60 => bodies.iter().step_by(2).for_each(|&b| {
                app.world_mut()
                    .entity_mut(b)
                    .insert(CollisionLayers::default());
            }),
            // A few bodies held still, then let go.
            90 => bodies.iter().skip(1).step_by(7).for_each(|&b| {
                app.world_mut().entity_mut(b).insert(RigidBody::Static);
            }),
            120 => bodies.iter().skip(1).step_by(7).for_each(|&b| {
                app.world_mut().entity_mut(b).insert(RigidBody::Dynamic);
            }),
            _ => {}
        }
    }
}

/// Pairs that avian takes out of its contact graph while their boxes overlap (a joint with
/// collisions disabled, a body disabled, a sensor made a plain collider), let in again
/// midway, are in the graph again as with
/// avian's own broad phase: the plugin looks for a pair in the graph only when it may not be
/// there.
#[test]
fn pairs_taken_out_of_the_graph_and_let_in_again_come_back() {
    for broad in [Broad::Default, Broad::Kinetic] {
        let mut app = app(broad);
        ground(&mut app);
        // Two stacks of two crates, and a third crate pressed half into a fourth.
        let unit = Vec3::ONE;
        let a = spawn(&mut app, cuboid(Vec3::new(-3.0, 0.5, 0.0), unit));
        let b = spawn(&mut app, cuboid(Vec3::new(-3.0, 1.5, 0.0), unit));
        let c = spawn(&mut app, cuboid(Vec3::new(3.0, 0.5, 0.0), unit));
        spawn(&mut app, cuboid(Vec3::new(3.0, 1.5, 0.0), unit));
        // A sensor sinking into the ground, made a plain crate again.
        let sensor = spawn(&mut app, (cuboid(Vec3::new(8.0, 0.5, 0.0), unit), Sensor));
        let mut joint = None;
        for k in 0..120 {
            let missing = step_missing(&mut app, 0.0);
            match k {
                10 => {
                    app.world_mut().entity_mut(sensor).remove::<Sensor>();
                }
                // The joint's crates sink into each other; the disabled crate stays put.
                30 => {
                    let j = (DistanceJoint::new(a, b), JointCollisionDisabled);
                    joint = Some(app.world_mut().spawn(j).id());
                    app.world_mut().entity_mut(c).insert(RigidBodyDisabled);
                }
                50 => {
                    let j = joint.expect("a joint");
                    app.world_mut()
                        .entity_mut(j)
                        .remove::<JointCollisionDisabled>();
                    app.world_mut().entity_mut(c).remove::<RigidBodyDisabled>();
                }
                _ => {}
            }
            if !(30..=52).contains(&k) {
                assert!(missing.is_empty(), "{broad:?}, step {k}: {missing:?}");
            }
        }
    }
}
