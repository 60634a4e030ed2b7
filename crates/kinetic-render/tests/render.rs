//! Rendering on the software adapter: golden images, read-back at an odd width, and where
//! things land.
//!
//! Golden images live in `tests/golden/`. A missing reference fails the test; `BLESS=1`
//! writes it (look at it before committing). On a mismatch the actual picture and the
//! difference are written next to the test's target folder, in `target/golden-failures/`.

use glam::{Quat, Vec3};
use kinetic_render::{AdapterChoice, Camera, Frame, HullMesh, Instance, Renderer, Snapshot};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A channel may differ by this much without counting. lavapipe (Vulkan) and llvmpipe (GL)
/// differed by at most one level on 9 of 307,200 pixels of a 640x480 MSAA frame (measured on
/// these machines, see DESIGN.md); 3 levels leave room for Mesa versions' rounding.
const LEVELS: u8 = 3;
/// And this fraction of pixels may differ by more: anti-aliased edges where the rasterisers
/// round coverage differently (0.2 % is 614 pixels of 640x480).
const PIXEL_FRACTION: f64 = 0.002;

fn renderer(width: u32, height: u32) -> Renderer {
    match Renderer::new(width, height, AdapterChoice::Software) {
        Ok(r) => r,
        Err(e) => panic!("these tests need Mesa's software adapter: {e}"),
    }
}

fn render(snapshot: &Snapshot, width: u32, height: u32) -> (Frame, Camera) {
    let camera = Camera::framing(snapshot, width as f32 / height as f32);
    let frame = renderer(width, height)
        .render(snapshot, &camera)
        .expect("render");
    (frame, camera)
}

fn check_golden(name: &str, frame: &Frame) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let reference = dir.join(format!("{name}.png"));
    if std::env::var_os("BLESS").is_some() {
        frame.save_png(&reference).expect("write the reference");
        return;
    }
    let Ok(expected) = Frame::load_png(&reference) else {
        panic!(
            "no reference image {}: run with BLESS=1 to write it, then look at it",
            reference.display()
        );
    };
    let diff = frame
        .difference(&expected, LEVELS)
        .expect("same size as the reference");
    let allowed = (PIXEL_FRACTION * f64::from(frame.width() * frame.height())) as usize;
    if diff.pixels_over > allowed {
        let out: PathBuf =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/golden-failures");
        frame
            .save_png(&out.join(format!("{name}.actual.png")))
            .expect("write actual");
        diff.image
            .save_png(&out.join(format!("{name}.diff.png")))
            .expect("write diff");
        panic!(
            "{name}: {} pixels differ by more than {LEVELS} levels (allowed {allowed}, largest {}); actual and difference in {}",
            diff.pixels_over,
            diff.max,
            out.display()
        );
    }
}

fn table() -> Snapshot {
    let mut s = Snapshot::new(Vec3::Z);
    s.instances.push(Instance::plane(
        Vec3::ZERO,
        Vec3::Z,
        4.0,
        [0.5, 0.5, 0.46, 1.0],
    ));
    s.instances.push(Instance::ball(
        Vec3::new(-1.0, 0.0, 1.0),
        1.0,
        [0.9, 0.06, 0.02, 1.0],
    ));
    s.instances.push(Instance::ball(
        Vec3::new(1.0, 0.0, 1.0),
        1.0,
        [0.9, 0.06, 0.02, 1.0],
    ));
    s.instances.push(Instance::ball(
        Vec3::new(2.5, 2.5, 0.3),
        0.3,
        [0.3, 0.45, 0.7, 1.0],
    ));
    s.instances.push(Instance::cuboid(
        Vec3::new(-2.0, 2.5, 0.5),
        Quat::from_rotation_z(0.6),
        Vec3::new(0.8, 0.4, 0.5),
        [0.55, 0.6, 0.35, 1.0],
    ));
    s
}

fn tetrahedron() -> HullMesh {
    HullMesh {
        points: vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ],
        // Deliberately mixed winding: the renderer turns faces outward itself.
        triangles: vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
    }
}

fn hulls_and_lines() -> Snapshot {
    let mut s = Snapshot::new(Vec3::Y);
    s.hulls = Arc::new(vec![tetrahedron()]);
    s.instances.push(Instance::hull(
        0,
        Vec3::ZERO,
        Quat::from_rotation_y(0.4),
        [0.55, 0.45, 0.7, 1.0],
    ));
    s.instances.push(Instance::hull(
        0,
        Vec3::new(3.0, 0.0, 0.0),
        Quat::from_rotation_x(1.0),
        [0.35, 0.6, 0.55, 1.0],
    ));
    s.instances.push(Instance::cuboid(
        Vec3::new(0.0, 0.0, 3.0),
        Quat::from_rotation_x(0.3),
        Vec3::new(1.0, 0.2, 0.6),
        [0.7, 0.6, 0.4, 1.0],
    ));
    s.wire_box(
        Vec3::new(-1.0, -1.0, -1.0),
        Vec3::new(1.0, 1.0, 1.0),
        [0.02, 0.1, 0.45, 1.0],
    );
    s.lines.push(kinetic_render::Line {
        a: Vec3::ZERO,
        b: Vec3::new(3.0, 0.0, 0.0),
        colour: [0.05, 0.05, 0.05, 1.0],
    });
    s
}

#[test]
fn golden_table_with_balls_and_a_box() {
    check_golden("table", &render(&table(), 320, 240).0);
}

#[test]
fn golden_hulls_cuboid_and_overlay_lines() {
    check_golden("hulls_and_lines", &render(&hulls_and_lines(), 320, 240).0);
}

#[test]
fn same_snapshot_same_pixels() {
    let s = table();
    let camera = Camera::framing(&s, 4.0 / 3.0);
    let mut r = renderer(160, 120);
    assert_eq!(
        r.render(&s, &camera).unwrap(),
        r.render(&s, &camera).unwrap()
    );
}

/// 199 pixels make rows of 796 bytes, not a multiple of 256: the read-back must drop each
/// row's padding. A padding slip would shear the picture, so the ball's red run must be
/// centred on its projection on every row it covers.
#[test]
fn read_back_at_a_width_whose_rows_are_padded() {
    let (w, h) = (199, 101);
    let mut s = Snapshot::new(Vec3::Z);
    s.instances
        .push(Instance::ball(Vec3::ZERO, 1.0, [0.9, 0.02, 0.02, 1.0]));
    s.instances.push(Instance::ball(
        Vec3::new(0.0, 0.0, -3.0),
        0.01,
        [0.9, 0.9, 0.9, 1.0],
    ));
    s.instances.push(Instance::ball(
        Vec3::new(0.0, 0.0, 3.0),
        0.01,
        [0.9, 0.9, 0.9, 1.0],
    ));
    let (frame, camera) = render(&s, w, h);
    assert_eq!(frame.rgba().len(), (w * h * 4) as usize);
    let (cx, cy) = camera.project(Vec3::ZERO, w, h).unwrap();
    let background = frame.pixel(0, 0).unwrap();
    let drawn = |p: [u8; 4]| p.iter().zip(background).any(|(a, b)| a.abs_diff(b) > 40);
    let red = |p: [u8; 4]| p[0] > p[1].saturating_add(30) && p[0] > p[2].saturating_add(30);
    let mut rows = 0;
    for y in 0..h {
        let xs: Vec<u32> = (0..w)
            .filter(|&x| drawn(frame.pixel(x, y).unwrap()))
            .collect();
        if xs.len() < 3 {
            continue;
        }
        rows += 1;
        let mid = (xs[0] + xs[xs.len() - 1]) as f32 / 2.0 + 0.5;
        assert!(
            (mid - cx).abs() < 1.5,
            "row {y}: ball's run centred at {mid}, projection at {cx}"
        );
        assert_eq!(
            xs.len() as u32,
            xs[xs.len() - 1] - xs[0] + 1,
            "row {y}: ball's run broken"
        );
    }
    assert!(rows > 10, "the ball covers {rows} rows");
    assert!(red(frame.pixel(cx as u32, cy as u32).unwrap()));
    assert!(!drawn(frame.pixel(w - 1, h - 1).unwrap()) && !drawn(frame.pixel(0, h - 1).unwrap()));
}

#[test]
fn bad_sizes_are_refused_with_the_limit() {
    let e = Renderer::new(0, 10, AdapterChoice::Software).unwrap_err();
    assert!(e.to_string().contains("0x10"), "{e}");
    let mut r = renderer(8, 8);
    let e = r.resize(1 << 20, 8).unwrap_err();
    assert!(e.to_string().contains("each side must be 1 to"), "{e}");
    assert_eq!(r.size(), (8, 8));
}

#[test]
fn a_missing_hull_is_an_error_not_a_panic() {
    let mut s = Snapshot::new(Vec3::Z);
    s.instances
        .push(Instance::hull(3, Vec3::ZERO, Quat::IDENTITY, [1.0; 4]));
    let camera = Camera::framing(&s, 1.0);
    let e = renderer(16, 16).render(&s, &camera).unwrap_err();
    assert!(e.to_string().contains("hull 3"), "{e}");
}

#[test]
fn png_round_trip() {
    let (frame, _) = render(&table(), 64, 48);
    let path = std::env::temp_dir().join(format!("kinetic-render-{}.png", std::process::id()));
    frame.save_png(&path).unwrap();
    assert_eq!(Frame::load_png(&path).unwrap(), frame);
    let _ = std::fs::remove_file(path);
}
