//! Bulk hard-sphere fluids in a periodic box: the pressure (collision virial) and the
//! collision rate against Enskog's theory with the Carnahan-Starling contact value, from
//! dilute gases to dense fluids melted from a lattice.

use kinetic_collide::FlightPlan;
use kinetic_collide::spheres::{ListedSpheres, PeriodicBox};
use kinetic_scenes::hard_spheres::HardSpheres;
use std::f64::consts::PI;

/// The fluid of `n` equal spheres at `packing`, equilibrated for `warm` collisions per sphere,
/// then measured over `measure` collisions per sphere: `(Z, collision rate, kT)`.
fn measure(n: usize, packing: f64, warm: f64, measure: f64) -> (f64, f64, f64) {
    let h = HardSpheres {
        n,
        packing,
        periodic: true,
        ..HardSpheres::gas(n)
    };
    let scene = h.build().unwrap();
    let cell = scene.periodic.unwrap();
    let spheres: Vec<(f64, FlightPlan)> = scene
        .objects
        .iter()
        .map(|o| (kinetic_collide::scene::outer_radius(&o.shape), o.plan()))
        .collect();
    let mut gas = ListedSpheres::periodic(
        PeriodicBox {
            min: cell.min,
            max: cell.max,
        },
        &spheres,
    )
    .unwrap();
    // Time for a number of collisions per sphere, from Enskog's rate.
    let per_sphere = 2.0 * h.collision_rate() / n as f64;
    gas.advance_to(warm / per_sphere).unwrap();
    gas.drain_events();
    gas.reset_bulk();
    let start = gas.now();
    gas.advance_to(start + measure / per_sphere).unwrap();
    gas.drain_events();
    gas.validate().unwrap();
    let b = gas.bulk();
    assert!((b.packing - packing).abs() < 1e-9);
    (b.compressibility, b.collision_rate, b.temperature)
}

#[test]
fn pressure_and_collision_rate_follow_enskog_carnahan_starling() {
    // The densest starts on a lattice: it melts within about 50 collisions per sphere.
    for (packing, warm) in [(0.1, 20.0), (0.2, 20.0), (0.3, 20.0), (0.45, 80.0)] {
        let (z, rate, kt) = measure(4000, packing, warm, 60.0);
        let eta: f64 = packing;
        let z_cs = (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3);
        // Enskog: Z - 1 = 4 eta g(sigma); rate per sphere 4 rho sigma^2 g sqrt(pi kT / m).
        let g = (z_cs - 1.0) / (4.0 * eta);
        let rho = 6.0 * eta / PI;
        let rate_enskog = 4.0 * rho * g * (PI * kt).sqrt();
        // 60 collisions per sphere over 4000 spheres: about 0.3% statistical error; CS is
        // within about 1% of simulations up to the freezing point.
        assert!(
            ((z - z_cs) / z_cs).abs() < 0.02,
            "packing {packing}: Z {z} against Carnahan-Starling {z_cs}"
        );
        assert!(
            ((rate - rate_enskog) / rate_enskog).abs() < 0.02,
            "packing {packing}: collision rate {rate} against Enskog {rate_enskog}"
        );
        assert!((kt - 1.0).abs() < 0.05, "kT {kt}");
    }
}
