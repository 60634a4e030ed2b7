//! An asteroid field: 400 spinning balls, cuboids and convex hulls whose sizes span three
//! orders of magnitude, in free flight through each other (no response), detected by guards
//! (Section 3.2). Writes the event log, statistics and 60 PNG frames (objects in contact in
//! red) to `out/asteroid_field/`.
//!
//! `cargo run --release --example asteroid_field -- [boxes|candidates] [N]`.

use kinetic_collide::Structure;
use kinetic_collide_cli::frames::{
    FrameSpec, Overlay, render_series, run_with_snapshots, write_run,
};
use kinetic_scenes::FlightScene;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let overlay = Overlay::parse(args.next().as_deref().unwrap_or("none"))?;
    let n = args.next().and_then(|a| a.parse().ok()).unwrap_or(400);
    let scene = FlightScene::asteroids(n, 1000.0, 3).build();
    let spec = FrameSpec {
        count: 60,
        overlay,
        ..FrameSpec::default()
    };
    let (output, snapshots) = run_with_snapshots(&scene, Some(Structure::Guards), &spec)?;
    let dir = Path::new("out/asteroid_field");
    write_run(dir, &scene, &output)?;
    println!("asteroid field: {}", output.summary());
    let start = std::time::Instant::now();
    let files = render_series(&snapshots, spec.width, spec.height, dir)?;
    println!(
        "wrote {} frames to {} in {:.1} s",
        files.len(),
        dir.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
