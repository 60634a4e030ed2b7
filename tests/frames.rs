//! Frames: the CLI writes them without changing the log, a missing adapter is a clear error
//! that keeps the log, and a highlighted contact lands where the camera projects it.

use kinetic_collide::run::run_scene;
use kinetic_collide::scene::Scene;
use kinetic_collide_cli::frames::{
    CONTACT, FrameSpec, Overlay, Painter, frame_times, run_with_snapshots,
};
use kinetic_render::{AdapterChoice, Camera, Renderer};
use std::path::PathBuf;
use std::process::Command;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "kinetic-collide-frames-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Two balls pass through each other (response none) while a third stays far away.
const PASSING: &str = r#"{"world": "free", "horizon": 4.0, "objects": [
  {"shape": {"ball": {"radius": 0.5}}, "position": [-2, 0, 0], "velocity": [1, 0, 0]},
  {"shape": {"ball": {"radius": 0.5}}, "position": [2, 0, 0], "velocity": [-1, 0, 0]},
  {"shape": {"cuboid": {"half_extents": [0.5, 0.5, 0.5]}}, "position": [0, 6, 0]},
  {"shape": {"convex_hull": {"points": [[1,1,1],[1,-1,-1],[-1,1,-1],[-1,-1,1]]}}, "position": [0, -6, 0],
   "angular_velocity": [0, 0, 1]}
]}"#;

fn tool_run(
    dir: &std::path::Path,
    extra: &[&str],
    env: Option<(&str, &str)>,
) -> (i32, String, String) {
    let scene = dir.join("passing.json");
    std::fs::write(&scene, PASSING).unwrap();
    let events = dir.join("events.jsonl");
    let _ = std::fs::remove_file(&events);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_kinetic-collide"));
    cmd.arg("run")
        .arg(&scene)
        .arg("--events")
        .arg(&events)
        .args(extra);
    if let Some((k, v)) = env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        std::fs::read_to_string(&events).unwrap_or_default(),
    )
}

#[test]
fn frames_are_written_and_the_log_is_unchanged() {
    let dir = temp_dir("written");
    let (code, stderr, plain) = tool_run(&dir, &[], None);
    assert_eq!(code, 0, "{stderr}");
    let out = dir.join("frames");
    let out_arg = out.to_str().unwrap();
    let (code, stderr, framed) = tool_run(
        &dir,
        &[
            "--frames",
            "5",
            "--out",
            out_arg,
            "--size",
            "99x61",
            "--overlay",
            "candidates",
        ],
        None,
    );
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(framed, plain, "frames must not change the log");
    assert_eq!(plain.lines().count(), 2, "{plain}");
    for k in 0..5 {
        let frame =
            kinetic_render::Frame::load_png(&out.join(format!("frame_{k:04}.png"))).unwrap();
        assert_eq!((frame.width(), frame.height()), (99, 61));
    }
    assert!(!out.join("frame_0005.png").exists());
}

#[test]
fn no_adapter_is_a_clear_error_and_the_log_is_still_written() {
    let dir = temp_dir("no-adapter");
    let (_, _, plain) = tool_run(&dir, &[], None);
    let out = dir.join("frames");
    // Metal is not built on Linux: wgpu finds no adapter at all.
    let (code, stderr, log) = tool_run(
        &dir,
        &["--frames", "3", "--out", out.to_str().unwrap()],
        Some(("WGPU_BACKEND", "metal")),
    );
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("no graphics adapter"), "{stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(
        stderr.contains("event log and statistics were written"),
        "{stderr}"
    );
    assert_eq!(log, plain);
    assert!(!out.join("frame_0000.png").exists());
}

#[test]
fn bad_frame_options_name_the_option() {
    let dir = temp_dir("bad-options");
    for (args, needle) in [
        (&["--frames", "2", "--size", "640by480"][..], "--size"),
        (&["--frames", "2", "--size", "0x480"][..], "each side"),
        (
            &["--frames", "2", "--overlay", "guards-and-more"][..],
            "--overlay",
        ),
    ] {
        let (code, stderr, log) = tool_run(&dir, args, None);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(log.is_empty());
    }
}

#[test]
fn frame_times_cover_the_horizon_evenly() {
    assert_eq!(frame_times(4.0, 5), vec![0.0, 1.0, 2.0, 3.0, 4.0]);
    assert_eq!(frame_times(4.0, 1), vec![0.0]);
    assert!(frame_times(4.0, 0).is_empty());
}

/// At t = 2 (the middle frame of five) balls 0 and 1 overlap (from t = 1.5 to 2.5): both are drawn in the contact
/// colour at their projected centres; the cuboid and the hull are not.
#[test]
fn a_highlighted_contact_appears_where_its_projection_says() {
    let scene = Scene::from_json(PASSING).unwrap();
    let spec = FrameSpec {
        count: 5,
        width: 320,
        height: 240,
        overlay: Overlay::None,
    };
    let (output, snapshots) = run_with_snapshots(&scene, None, &spec).unwrap();
    assert_eq!(output.events, run_scene(&scene, None).unwrap().events);
    assert_eq!(snapshots.len(), 5);
    let camera = Camera::framing_all(&snapshots, 320.0 / 240.0);
    let mut renderer = Renderer::new(320, 240, AdapterChoice::Software).expect("software adapter");
    let frame = renderer.render(&snapshots[2], &camera).unwrap();
    let contact = |p: [u8; 4]| p[0] > p[1].saturating_add(60) && p[0] > p[2].saturating_add(60);
    // Both balls are centred at the origin at t = 2: sample either side of it.
    for x in [-0.25f32, 0.25] {
        let (px, py) = camera
            .project(glam::Vec3::new(x, 0.0, 0.0), 320, 240)
            .unwrap();
        let p = frame.pixel(px as u32, py as u32).unwrap();
        assert!(
            contact(p),
            "ball at x = {x}: pixel {p:?} at ({px}, {py}) is not the contact colour {CONTACT:?}"
        );
    }
    for centre in [
        glam::Vec3::new(0.0, 6.0, 0.0),
        glam::Vec3::new(0.0, -6.0, 0.0),
    ] {
        let (px, py) = camera.project(centre, 320, 240).unwrap();
        let p = frame.pixel(px as u32, py as u32).unwrap();
        assert!(
            !contact(p) && p[0] < 200,
            "object at {centre}: pixel {p:?} should be drawn, not highlighted"
        );
    }
    // Before they meet (t = 0) nothing is highlighted.
    let first = renderer.render(&snapshots[0], &camera).unwrap();
    let (px, py) = camera
        .project(glam::Vec3::new(-2.0, 0.0, 0.0), 320, 240)
        .unwrap();
    assert!(!contact(first.pixel(px as u32, py as u32).unwrap()));
    // The painter draws every object once.
    let painter = Painter::new(&scene, Overlay::Boxes);
    let sweep = Some(kinetic_collide::Structure::Sweep);
    let (world, _) = kinetic_collide::run::build_world(&scene, sweep).unwrap();
    let s = painter.snapshot(&world, &[false; 4]);
    assert_eq!(s.instances.len(), 4);
    assert_eq!(s.lines.len(), 12 * 4, "the sweep's four boxes");
}
