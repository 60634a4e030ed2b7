//! A hard-sphere fluid in a periodic box: collisions per second, and the pressure against
//! Carnahan-Starling's equation of state.
//!
//! `cargo run --release -p kinetic-core --example periodic_gas -- [N] [PACKING] [COLLISIONS]`
//! (defaults: 32000 spheres, packing 0.26, 1e6 collisions; above 0.3 they start on a lattice).

use kinetic_core::{FlightPlan, PeriodicSpheres};
use kinetic_scenes::hard_spheres::HardSpheres;
use std::time::Instant;

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(32000.0) as usize;
    let packing = args.get(1).copied().unwrap_or(0.26);
    let collisions = args.get(2).copied().unwrap_or(1e6);
    let system = HardSpheres {
        n,
        packing,
        collisions,
        periodic: true,
        ..HardSpheres::gas(n)
    };
    let scene = match system.build() {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("periodic_gas: {e}");
            std::process::exit(2);
        }
    };
    let spheres: Vec<(f64, FlightPlan)> = scene
        .objects
        .iter()
        .map(|o| (kinetic_collide::scene::outer_radius(&o.shape), o.plan()))
        .collect();
    let start = Instant::now();
    let mut gas = PeriodicSpheres::new(scene.periodic.expect("a periodic box"), &spheres)
        .expect("a valid system");
    let mut t = 0.0;
    while t < scene.horizon {
        t = (t + 1.0).min(scene.horizon);
        gas.advance_to(t).expect("no Zeno in an elastic fluid");
        gas.drain_events();
    }
    let seconds = start.elapsed().as_secs_f64();
    let stats = gas.stats();
    let done = stats.events_by_kind.get("collision").copied().unwrap_or(0);
    let bulk = gas.bulk();
    let eta = bulk.packing;
    let z_cs = (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3);
    println!(
        "{n} spheres at packing {eta:.3}: {done} collisions in {seconds:.2} s, {:.0} per second",
        done as f64 / seconds
    );
    println!(
        "events {:?}; Z = PV/NkT {:.4} (Carnahan-Starling {z_cs:.4}), collision rate {:.4} per sphere",
        stats.events_by_kind, bulk.compressibility, bulk.collision_rate
    );
}
