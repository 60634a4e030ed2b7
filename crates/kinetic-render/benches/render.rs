//! Frame time: `cargo bench -p kinetic-render --bench render [-- --quick]`.
//!
//! Renders a field of balls and cuboids (half each) at 640x480 and 1920x1080 with 1e3 and 1e5
//! instances and reports the time per frame, read-back included, after one warm-up frame.
//! The adapter is the software one unless `KINETIC_RENDER_ADAPTER=gpu`.

use glam::{Quat, Vec3};
use kinetic_render::{AdapterChoice, Camera, Instance, Renderer, Snapshot};
use std::time::Instant;

fn field(n: usize) -> Snapshot {
    let mut s = Snapshot::new(Vec3::Z);
    let side = (n as f32).cbrt().ceil() as usize;
    for i in 0..n {
        let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
        let c = Vec3::new(x as f32, y as f32, z as f32) * 3.0;
        let colour = [0.3 + 0.1 * (i % 5) as f32, 0.45, 0.7, 1.0];
        s.instances.push(if i % 2 == 0 {
            Instance::ball(c, 1.0, colour)
        } else {
            Instance::cuboid(
                c,
                Quat::from_rotation_z(i as f32),
                Vec3::new(1.0, 0.7, 0.5),
                colour,
            )
        });
    }
    s
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let choice = AdapterChoice::from_env();
    for &(w, h) in &[(640u32, 480u32), (1920, 1080)] {
        let mut renderer = match Renderer::new(w, h, choice) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("render bench: {e}");
                std::process::exit(1);
            }
        };
        for &n in &[1_000usize, 100_000] {
            let s = field(n);
            let camera = Camera::framing(&s, w as f32 / h as f32);
            renderer.render(&s, &camera).expect("warm-up frame");
            let frames = if quick {
                2
            } else if n > 10_000 {
                5
            } else {
                20
            };
            let start = Instant::now();
            for _ in 0..frames {
                std::hint::black_box(renderer.render(&s, &camera).expect("frame"));
            }
            let ms = start.elapsed().as_secs_f64() * 1e3 / frames as f64;
            println!(
                "{:>4}x{:<4} {:>6} instances: {:8.1} ms/frame  ({})",
                w,
                h,
                n,
                ms,
                renderer.adapter()
            );
        }
    }
}
