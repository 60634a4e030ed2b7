//! Writes the rolling benchmark scene of `n` balls as a scene file:
//! `cargo run --release --example rolling_scene -- N HORIZON > scene.json`.

use kinetic_scenes::BallScene;

fn main() {
    let mut args = std::env::args().skip(1);
    let n = args.next().and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let horizon = args.next().and_then(|a| a.parse().ok()).unwrap_or(4.0);
    print!("{}", BallScene::rolling(n, horizon, 1).build().to_json());
}
