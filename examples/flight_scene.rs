//! Prints a free-flight scene (an asteroid field) as scene JSON:
//! `cargo run --release --example flight_scene -- N SIGMA [SEED] > scene.json`.

use kinetic_collide::scenes::FlightScene;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: f64| -> f64 {
        args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default)
    };
    let scene = FlightScene::asteroids(arg(0, 1000.0) as usize, arg(1, 1.0), arg(2, 1.0) as u64);
    print!("{}", scene.build().to_json());
}
