//! Marbles on a table: 300 balls of radii 1:50 rolling on a plane and bouncing elastically
//! inside the table's rim, detected by the rolling collision tree (Section 2). Writes the
//! event log, statistics and 60 PNG frames (balls that collided since the previous frame in
//! red) to `out/marbles_on_a_table/`.
//!
//! `cargo run --release --example marbles_on_a_table -- [boxes|candidates]` adds an overlay:
//! the tree's threshold boxes, or lines between candidate pairs.

use kinetic_collide_cli::frames::{
    FrameSpec, Overlay, render_series, run_with_snapshots, write_run,
};
use kinetic_scenes::BallScene;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let overlay = Overlay::parse(std::env::args().nth(1).as_deref().unwrap_or("none"))?;
    let scene = BallScene::marbles_on_a_table().build();
    let spec = FrameSpec {
        count: 60,
        overlay,
        ..FrameSpec::default()
    };
    let (output, snapshots) = run_with_snapshots(&scene, None, &spec)?;
    let dir = Path::new("out/marbles_on_a_table");
    write_run(dir, &scene, &output)?;
    println!("marbles on a table: {}", output.summary());
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
