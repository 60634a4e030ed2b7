//! Prints a free-flight scene as scene JSON:
//! `cargo run --release --example flight_scene -- N SIGMA [SEED] [nest] > scene.json`:
//! an asteroid field of mixed spinning shapes, or with `nest` the paper's Fig. 6 (clusters of
//! small balls under chains of ever larger balls).

use kinetic_scenes::{FlightScene, NestScene};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: f64| -> f64 {
        args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default)
    };
    let (n, sigma, seed) = (arg(0, 1000.0) as usize, arg(1, 1.0), arg(2, 1.0) as u64);
    let scene = if args.get(3).is_some_and(|a| a == "nest") {
        NestScene::new(n, sigma, seed).build()
    } else {
        FlightScene::asteroids(n, sigma, seed).build()
    };
    print!("{}", scene.to_json());
}
