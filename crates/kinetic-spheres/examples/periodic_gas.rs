//! A hard-sphere fluid in a periodic box: collisions per second, and the pressure against
//! Carnahan-Starling's equation of state.
//!
//! `cargo run --release -p kinetic-spheres --example periodic_gas -- [N] [PACKING] [COLLISIONS]`
//! (defaults: 32000 spheres of diameter 1, packing 0.26, 1e6 collisions). The spheres start
//! on a face-centred cubic lattice with random velocities at kT = 1 (the fluid melts from it
//! within a few dozen collisions per sphere); the run lasts about `COLLISIONS` collisions by
//! Enskog's rate.

use kinetic_core::{FlightPlan, Vec3};
use kinetic_spheres::{ListedSpheres, PeriodicBox};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::PI;
use std::time::Instant;

/// `n` spheres of diameter 1 at `packing` on an FCC lattice in a cubic box, with velocities
/// drawn at kT = 1 (mass 1) and no net momentum.
fn lattice(n: usize, packing: f64, seed: u64) -> (PeriodicBox, Vec<(f64, FlightPlan)>) {
    let side = (n as f64 * PI / 6.0 / packing).cbrt();
    let cells = ((n as f64 / 4.0).cbrt().ceil() as usize).max(1);
    let a = side / cells as f64;
    let basis = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut normal = || -> f64 { StandardNormal.sample(&mut rng) };
    let mut spheres = Vec::with_capacity(n);
    'fill: for i in 0..cells {
        for j in 0..cells {
            for k in 0..cells {
                for b in basis {
                    if spheres.len() == n {
                        break 'fill;
                    }
                    let p = Vec3::new(i as f64 + b[0], j as f64 + b[1], k as f64 + b[2]) * a;
                    spheres.push((
                        p + Vec3::splat(0.25 * a),
                        Vec3::new(normal(), normal(), normal()),
                    ));
                }
            }
        }
    }
    let mean = spheres.iter().map(|s| s.1).sum::<Vec3>() / n as f64;
    let kt = spheres
        .iter()
        .map(|s| (s.1 - mean).length_squared())
        .sum::<f64>()
        / (3 * n) as f64;
    let scale = 1.0 / kt.sqrt();
    let cell = PeriodicBox {
        min: Vec3::ZERO,
        max: Vec3::splat(side),
    };
    let plans = spheres
        .into_iter()
        .map(|(p, v)| (0.5, FlightPlan::linear(p, (v - mean) * scale)))
        .collect();
    (cell, plans)
}

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(32000.0) as usize;
    let packing = args.get(1).copied().unwrap_or(0.26);
    let collisions = args.get(2).copied().unwrap_or(1e6);
    if n < 2 || !(packing > 0.0 && packing < 0.74) {
        eprintln!("periodic_gas: need at least 2 spheres and a packing in (0, 0.74)");
        std::process::exit(2);
    }
    let (cell, spheres) = lattice(n, packing, 1);
    // Enskog's collision rate per sphere, 4 rho g(1) sqrt(pi kT / m) with Carnahan-Starling's
    // contact value g(1); the system's rate is n / 2 times that.
    let eta = packing;
    let z_cs = (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3);
    let g = (z_cs - 1.0) / (4.0 * eta);
    let rate = 4.0 * (6.0 * eta / PI) * g * PI.sqrt() * n as f64 / 2.0;
    let horizon = collisions / rate;
    let start = Instant::now();
    let mut gas = match ListedSpheres::periodic(cell, &spheres) {
        Ok(gas) => gas,
        Err(e) => {
            eprintln!("periodic_gas: {e}");
            std::process::exit(2);
        }
    };
    let mut t = 0.0;
    while t < horizon {
        t = (t + 1.0).min(horizon);
        gas.advance_to(t).expect("no Zeno in an elastic fluid");
        gas.drain_events();
    }
    let seconds = start.elapsed().as_secs_f64();
    let stats = gas.stats();
    let done = stats.events_by_kind.get("collision").copied().unwrap_or(0);
    let bulk = gas.bulk();
    println!(
        "{n} spheres at packing {:.3}: {done} collisions in {seconds:.2} s, {:.0} per second",
        bulk.packing,
        done as f64 / seconds
    );
    println!(
        "events {:?}; Z = PV/NkT {:.4} (Carnahan-Starling {z_cs:.4}), collision rate {:.4} per sphere",
        stats.events_by_kind, bulk.compressibility, bulk.collision_rate
    );
}
