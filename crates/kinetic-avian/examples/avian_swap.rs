//! avian3d 0.8 with the kinetic broad phase swapped in (one plugin), headless: a rain of balls
//! and boxes onto a ground. Prints per-step broad-phase time and pairs, and writes the last
//! step as a PNG frame through kinetic-render.
//!
//! `cargo run --release -p kinetic-avian --example avian_swap -- [N] [STEPS]` (default 1000
//! bodies, 240 steps at 64 Hz). Writes `out/avian_swap.png`.

use avian3d::prelude::*;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use kinetic_avian::{KineticBroadPhase, KineticBroadPhasePlugin};
use kinetic_render::{AdapterChoice, Camera, Instance, Renderer, Snapshot, glam};
use std::time::Duration;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let steps: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(240);

    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    // The swap: avian's BVH broad phase off, the kinetic one on.
    app.add_plugins(
        PhysicsPlugins::default()
            .build()
            .disable::<BvhBroadPhasePlugin>()
            .add(KineticBroadPhasePlugin::new()),
    );
    // One physics step per update, at 64 Hz, however fast the machine runs.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / 64.0,
    )));
    app.finish();
    let scene = kinetic_scenes::engines::rain(n, (n / 400).max(3), 7);
    kinetic_scenes::avian::spawn(&scene, app.world_mut());

    println!("{n} bodies, {steps} steps at 64 Hz, structure picked from the first colliders");
    println!("step  broad phase (ms)  live pairs  added  contacts  touching");
    for step in 0..steps {
        app.update();
        if step % 20 == 19 || step + 1 == steps {
            let world = app.world();
            let kinetic = world.resource::<KineticBroadPhase>();
            let (added, time) = kinetic.last_added();
            let graph = world.resource::<ContactGraph>();
            println!(
                "{:4}  {:16.3}  {:10}  {:5}  {:8}  {:8}",
                step + 1,
                time.as_secs_f64() * 1e3,
                kinetic.live_pairs(),
                added,
                graph.iter_active().count(),
                graph.iter_active_touching().count(),
            );
        }
    }
    let kinetic = app.world().resource::<KineticBroadPhase>();
    let s = kinetic.stats();
    println!(
        "structure {}: {} events, {} re-plans, {} pairs added to the contact graph",
        kinetic.structure_name(),
        s.events,
        s.replans,
        kinetic.added()
    );

    let snapshot = snapshot(app.world_mut());
    let path = std::path::Path::new("out/avian_swap.png");
    let written = std::fs::create_dir_all("out")
        .map_err(|e| e.to_string())
        .and_then(|()| {
            let mut renderer =
                Renderer::new(640, 480, AdapterChoice::Software).map_err(|e| e.to_string())?;
            let camera = Camera::framing(&snapshot, 640.0 / 480.0);
            let frame = renderer
                .render(&snapshot, &camera)
                .map_err(|e| e.to_string())?;
            frame.save_png(path).map_err(|e| e.to_string())
        });
    match written {
        Ok(()) => println!("wrote {}", path.display()),
        Err(e) => println!("no frame written: {e}"),
    }
}

/// The colliders now: the ground grey, bodies in contact red, the others blue.
fn snapshot(world: &mut World) -> Snapshot {
    let mut touching = std::collections::HashSet::new();
    for pair in world.resource::<ContactGraph>().iter_active_touching() {
        touching.insert(pair.collider1);
        touching.insert(pair.collider2);
    }
    let mut q = world.query::<(Entity, &Collider, &Position, &Rotation, &RigidBody)>();
    let mut s = Snapshot::new(glam::Vec3::Y);
    for (e, collider, pos, rot, rb) in q.iter(world) {
        let colour = if rb.is_static() {
            [0.50, 0.50, 0.46, 1.0]
        } else if touching.contains(&e) {
            [0.90, 0.06, 0.02, 1.0]
        } else {
            [0.30, 0.45, 0.70, 1.0]
        };
        let centre = glam::Vec3::from_array(pos.0.to_array());
        let rotation = glam::Quat::from_array(rot.0.to_array());
        if let Some(ball) = collider.shape().as_ball() {
            s.instances
                .push(Instance::ball(centre, ball.radius, colour));
        } else if let Some(cuboid) = collider.shape().as_cuboid() {
            let h = glam::Vec3::from_array(cuboid.half_extents.to_array());
            s.instances
                .push(Instance::cuboid(centre, rotation, h, colour));
        }
    }
    s
}
