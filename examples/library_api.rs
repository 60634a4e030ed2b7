//! The library API in a few lines: build a world, add balls with flight plans, change a plan,
//! advance, drain the contact events. `cargo run --release --example library_api`.

use kinetic_collide::{FlightPlan, Response, Vec3, Walls, World, WorldError, WorldKind};

fn main() -> Result<(), WorldError> {
    let walls = Walls {
        min: Vec3::splat(-10.0),
        max: Vec3::splat(10.0),
    };
    let mut world = World::with_structure(
        WorldKind::Free,
        Response::Elastic,
        Some(walls),
        kinetic_collide::Structure::BruteForce,
    )?;
    let cue = world.add_ball(
        0.5,
        FlightPlan::linear(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)),
    )?;
    for i in 0..3 {
        world.add_ball(
            0.5,
            FlightPlan::at_rest(Vec3::new(2.0 + 1.1 * f64::from(i), 0.0, 0.0)),
        )?;
    }
    world.advance_to(1.0)?;
    // A push: the cue ball gets a sideways component from t = 1 on.
    let plan = world
        .body(cue)
        .map(|b| b.plan)
        .expect("the cue ball is live");
    world.set_plan(cue, plan.replanned(1.0, Vec3::new(3.0, 0.2, 0.0)))?;
    world.advance_to(10.0)?;
    for e in world.drain_events() {
        println!("t = {:.6}: balls {} and {} collide", e.time, e.a.0, e.b.0);
    }
    println!(
        "{} wall bounces, {} events in all",
        world.stats().bounces,
        world.stats().events_total()
    );
    Ok(())
}
