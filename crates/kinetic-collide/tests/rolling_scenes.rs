//! The rolling-ball collision tree (both list layouts) against the brute-force reference on
//! seeded random plane scenes, with `validate()` after every event, plus named degenerate
//! cases.

use kinetic_collide::Structure;
use kinetic_collide::run::build_world;
use kinetic_collide::scene::{Scene, SceneObject};
use kinetic_collide::{ContactEvent, Response, Vec3, World, WorldKind};
use kinetic_scenes::BallScene;

/// The rolling tree in both layouts, and the box structures, which hold a rolling ball by
/// its disc (contact at 2 sqrt(ra rb) is never farther than ra + rb).
const LAYOUTS: [Structure; 5] = [
    Structure::RollingTree,
    Structure::RollingGlobalLists,
    Structure::Sweep,
    Structure::Grid,
    Structure::LooseGrid,
];

/// How many events of a run get the full audit (O(n log^2 n) each) after them: every one for
/// the tree; the first 20,000 for the others (the global lists make twenty to fifty times as
/// many events, a million in the dense scene; auditing all would take ten minutes here).
fn audited(layout: Structure) -> usize {
    match layout {
        Structure::RollingTree => usize::MAX,
        // The box structures are audited after every event in the free-flight tests; here,
        // on the plane, the first 20,000 events and the whole log against the brute force.
        _ => 20_000,
    }
}

/// Runs `world` to `horizon`, validating after each of the first `audited` events; returns
/// the log.
fn run_validated(world: &mut World, horizon: f64, audited: usize) -> Vec<ContactEvent> {
    world.validate().unwrap_or_else(|e| panic!("at start: {e}"));
    let mut events = 0;
    while world.step(horizon).unwrap().is_some() {
        events += 1;
        if events <= audited {
            world.validate().unwrap_or_else(|e| {
                panic!("{} at t = {}: {e}", world.structure_name(), world.now())
            });
        }
    }
    world.advance_to(horizon).unwrap();
    world
        .validate()
        .unwrap_or_else(|e| panic!("at the horizon: {e}"));
    world.drain_events()
}

fn run(scene: &Scene, structure: Structure) -> Vec<ContactEvent> {
    let (mut world, _) = build_world(scene, Some(structure)).unwrap();
    world.advance_to(scene.horizon).unwrap();
    world.drain_events()
}

/// Two logs are the same: the same pairs and kinds in the same order, times within the
/// scene format's accuracy.
fn assert_same_log(reference: &[ContactEvent], got: &[ContactEvent], what: &str) {
    let first_diff = reference.iter().zip(got).position(|(r, g)| {
        (r.a, r.b, r.kind) != (g.a, g.b, g.kind)
            || (r.time - g.time).abs() > 1e-7 * r.time.abs().max(1.0)
    });
    assert!(
        first_diff.is_none() && reference.len() == got.len(),
        "{what}: logs differ at event {:?} of {} / {}: reference {:?}, got {:?}",
        first_diff,
        reference.len(),
        got.len(),
        first_diff.map(|i| reference[i]),
        first_diff.map(|i| got[i]),
    );
}

/// The rolling bench scene with other radii and side: no response, linear, horizon 10.
fn plane(n: usize, r_min: f64, r_max: f64, side: f64, seed: u64) -> BallScene {
    BallScene {
        r_min,
        r_max,
        side,
        ..BallScene::rolling(n, 10.0, seed)
    }
}

/// Runs `params` with the brute force and with both layouts of the collision tree: the logs
/// must match to the horizon (the tree validated as `run_validated` says).
fn check_against_brute_force(params: BallScene) -> usize {
    let scene = params.build();
    let reference = run(&scene, Structure::BruteForce);
    for layout in LAYOUTS {
        let (mut world, _) = build_world(&scene, Some(layout)).unwrap();
        let got = run_validated(&mut world, scene.horizon, audited(layout));
        assert_same_log(
            &reference,
            &got,
            &format!("{} on {params:?}", layout.name()),
        );
    }
    reference.len()
}

#[test]
fn sparse_linear_three_orders_of_radii() {
    let mut events = 0;
    for seed in 0..3 {
        events += check_against_brute_force(plane(200, 0.01, 10.0, 300.0, seed));
    }
    assert!(events > 30, "too few events to test anything: {events}");
}

#[test]
fn dense_linear_three_orders_of_radii() {
    let events = check_against_brute_force(plane(500, 0.01, 10.0, 120.0, 7));
    assert!(events > 400, "{events}");
}

#[test]
fn accelerated_mixed_sizes() {
    let mut params = plane(300, 0.01, 10.0, 150.0, 3);
    params.acceleration = 0.3;
    let events = check_against_brute_force(params);
    assert!(events > 100, "{events}");
}

#[test]
fn elastic_in_a_box_with_walls() {
    let mut params = plane(300, 0.01, 10.0, 200.0, 5);
    params.response = Response::Elastic;
    params.walls = true;
    params.allow_overlap = false;
    params.speed = 3.0;
    let events = check_against_brute_force(params);
    assert!(events > 50, "{events}");
}

#[test]
fn elastic_accelerated_dense() {
    let mut params = plane(400, 0.02, 2.0, 80.0, 11);
    params.response = Response::Elastic;
    params.walls = true;
    params.allow_overlap = false;
    params.acceleration = 0.5;
    let events = check_against_brute_force(params);
    assert!(events > 100, "{events}");
}

// --- Named degenerate cases -------------------------------------------------------------

fn scene_of(world: WorldKind, response: Response, balls: &[(f64, [f64; 2], [f64; 2])]) -> Scene {
    let mut objects = Vec::new();
    for &(r, p, v) in balls {
        objects.push(SceneObject::ball(
            r,
            Vec3::new(p[0], p[1], 0.0),
            Vec3::new(v[0], v[1], 0.0),
        ));
    }
    Scene {
        world,
        horizon: 10.0,
        response,
        walls: None,
        periodic: None,
        objects,
    }
}

fn check_scene(scene: &Scene) -> Vec<ContactEvent> {
    let reference = run(scene, Structure::BruteForce);
    for layout in LAYOUTS {
        let (mut world, _) = build_world(scene, Some(layout)).unwrap();
        let got = run_validated(&mut world, scene.horizon, audited(layout));
        assert_same_log(&reference, &got, layout.name());
    }
    reference
}

#[test]
fn all_radii_equal() {
    for response in [Response::None, Response::Elastic] {
        let mut params = plane(300, 0.5, 0.5, 60.0, 21);
        params.response = response;
        params.allow_overlap = response == Response::None;
        params.walls = response == Response::Elastic;
        let events = check_against_brute_force(params);
        assert!(events > 50, "{response:?}: {events}");
    }
}

#[test]
fn simultaneous_swaps_on_a_grid() {
    // Balls on a lattice share x and y coordinates; rows move along x, columns along y, so
    // many points cross many box sides at the same instants, and equal radii meet exactly on
    // box edges.
    let mut balls = Vec::new();
    for i in 0..12 {
        for j in 0..12 {
            let r = if (i + j) % 3 == 0 { 0.25 } else { 1.0 };
            let v = match (i + 2 * j) % 4 {
                0 => [1.0, 0.0],
                1 => [0.0, -1.0],
                2 => [-0.5, 0.0],
                _ => [0.0, 0.0],
            };
            balls.push((r, [4.0 * i as f64, 4.0 * j as f64], v));
        }
    }
    for response in [Response::None, Response::Elastic] {
        let events = check_scene(&scene_of(WorldKind::Plane, response, &balls));
        assert!(events.len() > 100, "{response:?}: {}", events.len());
    }
}

#[test]
fn ball_starting_in_contact() {
    // Touching (tangency points exactly 2 sqrt(r1 r2) apart), overlapping, and touching while
    // moving apart.
    let balls = [
        (1.0, [0.0, 0.0], [0.0, 0.0]),
        (0.25, [2.0 * 0.5, 0.0], [0.0, 0.0]),
        (4.0, [0.0, 20.0], [0.0, 0.0]),
        (1.0, [0.0, 23.0], [0.0, 1.0]),
        (0.5, [40.0, 0.0], [-1.0, 0.0]),
        (0.5, [41.0, 0.0], [1.0, 0.0]),
    ];
    let events = check_scene(&scene_of(WorldKind::Plane, Response::None, &balls));
    let at_zero = events.iter().filter(|e| e.time == 0.0).count();
    assert!(at_zero >= 4, "contacts at t = 0: {events:?}");
}

#[test]
fn one_huge_ball_among_tiny_ones() {
    // Radius 1000 (its threshold boxes dwarf every other) among 300 balls of 0.01 to 0.1
    // crossing its rim: a ball of radius r touches it 2 sqrt(1000 r) (6 to 20) from its
    // tangency point.
    let mut params = plane(300, 0.01, 0.1, 60.0, 5);
    params.speed = 4.0;
    let mut scene = params.build();
    scene.objects.push(SceneObject::ball(
        1000.0,
        Vec3::new(30.0, 30.0, 0.0),
        Vec3::ZERO,
    ));
    let events = check_scene(&scene);
    let with_huge = events.iter().filter(|e| e.b.0 == 300).count();
    assert!(with_huge > 20, "contacts with the huge ball: {with_huge}");
}

#[test]
fn coordinates_offset_by_1e6() {
    let params = plane(200, 0.01, 10.0, 150.0, 9);
    let mut scene = params.build();
    let near = run(&scene, Structure::BruteForce);
    for o in &mut scene.objects {
        o.position += Vec3::new(1e6, -1e6, 0.0);
    }
    let far = check_scene(&scene);
    // Far from the origin the same contacts happen, at times within rounding of 1e6.
    assert_eq!(near.len(), far.len());
    for (a, b) in near.iter().zip(&far) {
        assert_eq!((a.a, a.b, a.kind), (b.a, b.b, b.kind));
        assert!((a.time - b.time).abs() < 1e-6, "{a:?} vs {b:?}");
    }
}

/// The same script of additions, removals and pushes, on a world with `structure`.
fn churn(
    structure: Structure,
    audit_events: bool,
) -> (Vec<ContactEvent>, Vec<(&'static str, f64)>) {
    use kinetic_collide::{FlightPlan, ObjectId};
    use rand::{Rng, SeedableRng};
    let scene = plane(150, 0.05, 5.0, 80.0, 13).build();
    let (mut world, _) = build_world(&scene, Some(structure)).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(99);
    let mut live: Vec<u32> = (0..150).collect();
    let mut log = Vec::new();
    for round in 1..=30 {
        let t = 0.4 * round as f64;
        // The tree audits every event; the global lists the round's first thousand.
        let audit = match (audit_events, structure) {
            (false, _) => 0,
            (true, Structure::RollingGlobalLists) => 1000,
            (true, _) => usize::MAX,
        };
        log.extend(run_validated(&mut world, t, audit));
        // Rounds 10 to 14 add balls larger than all before (each joins the large half of
        // every node on its way): the tree must rebuild to stay balanced.
        for k in 0..8 {
            let r = if (10..15).contains(&round) {
                10.0 + (round * 8 + k) as f64
            } else {
                rng.random_range(0.01f64.ln()..5f64.ln()).exp()
            };
            let p = Vec3::new(
                rng.random_range(0.0..80.0),
                rng.random_range(0.0..80.0),
                0.0,
            );
            let v = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                0.0,
            );
            let plan = FlightPlan::linear(p, v).starting_at(t);
            live.push(world.add_ball(r, plan).unwrap().0);
        }
        for _ in 0..if round > 20 { 12 } else { 4 } {
            let id = live.swap_remove(rng.random_range(0..live.len()));
            world.remove(ObjectId(id)).unwrap();
        }
        for _ in 0..3 {
            let id = ObjectId(live[rng.random_range(0..live.len())]);
            let plan = world.body(id).unwrap().plan;
            let v = Vec3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                0.0,
            );
            world.set_plan(id, plan.replanned(t, v)).unwrap();
        }
        world
            .validate()
            .unwrap_or_else(|e| panic!("after round {round}: {e}"));
    }
    log.extend(world.drain_events());
    (log, world.structure_counters())
}

#[test]
fn balls_added_and_removed_mid_run() {
    let (reference, _) = churn(Structure::BruteForce, false);
    assert!(reference.len() > 100, "{}", reference.len());
    for layout in LAYOUTS {
        let (got, counters) = churn(layout, true);
        assert_same_log(&reference, &got, layout.name());
        if !matches!(
            layout,
            Structure::RollingTree | Structure::RollingGlobalLists
        ) {
            continue;
        }
        let counter = |name| counters.iter().find(|c| c.0 == name).unwrap().1;
        assert!(counter("subtree_rebuilds") > 0.0, "{counters:?}");
        // Weight balance (no half above 3/4 of its node, plus one) bounds the depth by
        // about log_{4/3} n; the live balls number at most 150 + 240.
        assert!(
            counter("tree_depth") <= (390f64).ln() / (4.0f64 / 3.0).ln() + 2.0,
            "{counters:?}"
        );
    }
}

/// The most threshold boxes (of one node) that held one tangency point during a short elastic
/// run of `n` disjoint balls, radii over three orders of magnitude, at a fixed density.
fn most_boxes_per_point(n: usize) -> f64 {
    let mut params = plane(n, 0.01, 10.0, 4.0 * (n as f64).sqrt(), 4);
    params.response = Response::Elastic;
    params.walls = true;
    params.allow_overlap = false;
    params.horizon = 1.0;
    let scene = params.build();
    let (mut world, _) = build_world(&scene, Some(Structure::RollingTree)).unwrap();
    // Lemma 2 is about disjoint balls: none may overlap at the start (the elastic response
    // keeps them apart).
    world.advance_to(0.0).unwrap();
    assert!(
        world.drain_events().is_empty(),
        "overlapping balls at n = {n}"
    );
    world.advance_to(scene.horizon).unwrap();
    world.validate().unwrap();
    let counters = world.structure_counters();
    counters
        .iter()
        .find(|c| c.0 == "max_boxes_per_point")
        .unwrap()
        .1
}

#[test]
fn lemma_4_boxes_per_point_stay_bounded() {
    let most: Vec<f64> = [100, 1000, 10_000].map(most_boxes_per_point).to_vec();
    eprintln!("most boxes per point at n = 100, 1000, 10000: {most:?}");
    // Lemma 4 (Lemma 2 with c = sqrt 2): at most (8 c^2 + 2 c + 1)^2 + 1 < 394.
    assert!(most.iter().all(|&m| (1.0..394.0).contains(&m)), "{most:?}");
    // And it does not creep up with n: log2 n grows by 6.6 from the first to the last.
    assert!(most[2] <= most[0] + 2.0, "{most:?}");
}
