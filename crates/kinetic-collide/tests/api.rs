//! The library's surface as a user meets it: the world and every structure can move to
//! another thread or sit in a shared resource, and errors convert with `?` across crates.

use kinetic_collide::kds::{BruteForce, Grid, Guards, LooseGrid, RollingTree, Sweep};
use kinetic_collide::run::RunError;
use kinetic_collide::scene::Scene;
use kinetic_collide::{ConvexShape, FlightPlan, Structure, Vec3, World, WorldError, WorldKind};

fn send_sync<T: Send + Sync>() {}

#[test]
fn the_world_and_every_structure_are_send_and_sync() {
    send_sync::<World>();
    send_sync::<BruteForce>();
    send_sync::<Sweep>();
    send_sync::<Guards>();
    send_sync::<Grid>();
    send_sync::<LooseGrid>();
    send_sync::<RollingTree>();
    send_sync::<kinetic_collide::spheres::ElasticCells>();
    // And it runs on another thread.
    let mut world = World::new(WorldKind::Free);
    world
        .add_ball(1.0, FlightPlan::at_rest(Vec3::ZERO))
        .unwrap();
    let handle = std::thread::spawn(move || {
        world.advance_to(1.0).unwrap();
        world.now()
    });
    assert_eq!(handle.join().unwrap(), 1.0);
}

/// `World::new` gets the fast structure for what it holds: the brute force for a few dozen
/// objects, then a box structure by their sizes; it reads as a user writes it
/// (`world.advance_to(world.now() + dt)`).
#[test]
fn the_default_world_picks_its_structure_by_the_objects_it_holds() {
    // Without the race, whose trials depend on the clock.
    let mut world = World::new(WorldKind::Free).without_racing();
    assert_eq!(world.structure_name(), "brute-force");
    for k in 0..50 {
        let p = Vec3::new(3.0 * k as f64, 0.0, 0.0);
        world.add_ball(1.0, FlightPlan::linear(p, Vec3::X)).unwrap();
        let want = if k < 32 { "brute-force" } else { "grid" };
        assert_eq!(world.structure_name(), want, "{} balls", k + 1);
    }
    world.advance_to(world.now() + 1.0).unwrap();
    assert_eq!(world.structure_name(), "grid");
    // Its footprints (twelve certificates a ball) and the few neighbours' pairs, not the
    // brute force's 1,225 pairs.
    assert!(
        world.certificates() < 700,
        "{} certificates",
        world.certificates()
    );
    // A boulder 1e4 times larger among these few: the sweep, whose sorted lists do not care
    // about sizes.
    world
        .add_ball(1e4, FlightPlan::at_rest(Vec3::new(0.0, 5e5, 0.0)))
        .unwrap();
    assert_eq!(world.structure_name(), "sweep");
    world.advance_to(world.now() + 1.0).unwrap();
    world.validate().unwrap();
    // The simulator without the flight crate keeps the brute force.
    let core = kinetic_collide::kds::Simulator::new(WorldKind::Free);
    assert_eq!(core.structure_name(), "brute-force");
}

/// A shape error becomes a world error with `?`.
fn add_cuboid(world: &mut World, half: Vec3) -> Result<(), WorldError> {
    let shape = ConvexShape::cuboid(half)?;
    world.add_object(shape.into_shape(), FlightPlan::at_rest(Vec3::ZERO))?;
    Ok(())
}

/// Scene and world errors become run errors with `?`.
fn load(text: &str) -> Result<usize, RunError> {
    let scene = Scene::from_json(text)?;
    let mut world = World::new(WorldKind::Free);
    world.add_ball(-1.0, FlightPlan::at_rest(Vec3::ZERO))?;
    Ok(scene.objects.len())
}

#[test]
fn errors_convert_across_crates() {
    let mut world = World::new(WorldKind::Free);
    assert!(add_cuboid(&mut world, Vec3::ONE).is_ok());
    let err = add_cuboid(&mut world, Vec3::new(1.0, -1.0, 1.0)).unwrap_err();
    assert!(matches!(err, WorldError::InvalidShape(_)), "{err}");
    let err = load("{").unwrap_err();
    assert!(err.to_string().contains("not valid JSON"), "{err}");
    let err = load(r#"{"world": "free", "horizon": 1, "objects": []}"#).unwrap_err();
    assert!(err.to_string().contains("radius"), "{err}");
    // Magnitudes beyond the range are refused by the world too.
    let err = world
        .add_ball(1.0, FlightPlan::at_rest(Vec3::new(1e200, 0.0, 0.0)))
        .unwrap_err();
    assert!(matches!(err, WorldError::OutOfRange { .. }), "{err}");
}

#[test]
fn a_zeno_trap_at_a_wall_names_the_object_and_the_wall() {
    let wall = WorldError::Zeno {
        time: 1.0,
        limit: 10,
        a: 1,
        b: 1,
    };
    assert!(
        wall.to_string().contains("object 1 against a wall"),
        "{wall}"
    );
    let pair = WorldError::Zeno {
        time: 1.0,
        limit: 10,
        a: 1,
        b: 2,
    };
    assert!(pair.to_string().contains("objects 1 and 2"), "{pair}");
}

/// Every structure builds into a world where it applies, and says why where it does not.
#[test]
fn every_structure_by_name_builds_a_world_or_says_why_not() {
    for s in Structure::ALL {
        for kind in [WorldKind::Free, WorldKind::Plane] {
            let built = World::with_structure(kind, kinetic_collide::Response::None, None, s);
            let applies = match s {
                Structure::Cells | Structure::Lists | Structure::Periodic => false,
                Structure::RollingTree | Structure::RollingGlobalLists => kind == WorldKind::Plane,
                Structure::Guards => kind == WorldKind::Free,
                _ => true,
            };
            match built {
                Ok(world) => {
                    assert!(applies, "{s} built in a {kind:?} world");
                    assert_eq!(world.structure_name(), s.name());
                }
                Err(e) => {
                    assert!(!applies, "{s} in a {kind:?} world: {e}");
                    assert!(matches!(e, WorldError::UnsupportedStructure { .. }), "{e}");
                    assert!(e.to_string().contains(s.name()), "{e}");
                }
            }
        }
    }
}

/// The front door stays small: at most 25 names at the crate's root, each once.
#[test]
fn the_root_exports_at_most_25_names_each_once() {
    let lib = include_str!("../src/lib.rs");
    let mut names = Vec::new();
    let mut depth = 0usize;
    let mut statement = String::new();
    for line in lib.lines() {
        let code = line.split("//").next().unwrap_or("").trim();
        if depth == 0 && (code.starts_with("pub use") || code.starts_with("pub mod")) {
            statement.clear();
        }
        if depth == 0
            && (code.starts_with("pub use") || code.starts_with("pub mod") || !statement.is_empty())
        {
            statement.push_str(code);
            statement.push(' ');
            if code.ends_with(';') || code.ends_with('{') {
                let s = statement
                    .trim()
                    .trim_end_matches(['{', ';'])
                    .trim()
                    .to_string();
                statement.clear();
                if let Some(m) = s.strip_prefix("pub mod ") {
                    names.push(m.to_string());
                } else if let Some(u) = s.strip_prefix("pub use ") {
                    let inner = u
                        .split_once('{')
                        .map_or(u, |(_, rest)| rest.trim_end_matches('}'));
                    for item in inner.split(',') {
                        let item = item.trim();
                        if item.is_empty() {
                            continue;
                        }
                        let name = item.rsplit(" as ").next().unwrap_or(item);
                        names.push(name.rsplit("::").next().unwrap_or(name).to_string());
                    }
                }
            }
        }
        depth += code.matches('{').count();
        depth -= code.matches('}').count().min(depth);
    }
    assert!(names.len() >= 10, "the scan found {names:?}");
    assert!(
        names.len() <= 25,
        "{} names at the root: {names:?}",
        names.len()
    );
    let mut sorted = names.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), names.len(), "a name twice: {names:?}");
}
