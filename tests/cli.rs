//! The command-line tool end to end: valid scenes, every error case of the scene format,
//! whole-or-nothing output, determinism.

use std::path::{Path, PathBuf};
use std::process::Command;

fn tool() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kinetic-collide"))
}

fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("kinetic-collide-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `scene` and returns (status, stderr, events file text if written, stats if written).
fn run(dir: &Path, scene: &str, extra: &[&str]) -> (i32, String, Option<String>, Option<String>) {
    let path = dir.join("scene.json");
    std::fs::write(&path, scene).unwrap();
    let (events, stats) = (dir.join("events.jsonl"), dir.join("stats.json"));
    let _ = std::fs::remove_file(&events);
    let _ = std::fs::remove_file(&stats);
    let out = tool()
        .arg("run")
        .arg(&path)
        .arg("--events")
        .arg(&events)
        .arg("--stats")
        .arg(&stats)
        .args(extra)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        std::fs::read_to_string(&events).ok(),
        std::fs::read_to_string(&stats).ok(),
    )
}

const BALL: &str =
    r#"{"shape": {"ball": {"radius": 0.5}}, "position": [0, 0, 0], "velocity": [1, 0, 0]}"#;

fn scene_with(top: &str, objects: &[&str]) -> String {
    format!("{{{top}, \"objects\": [{}]}}", objects.join(", "))
}

#[test]
fn small_scene_gives_the_exact_log() {
    let dir = temp_dir("small");
    let scene = scene_with(
        r#""world": "free", "horizon": 10.0"#,
        &[
            BALL,
            r#"{"shape": {"ball": {"radius": 0.5}}, "position": [5, 1, 0]}"#,
            r#"{"shape": {"ball": {"radius": 0.5}}, "position": [5, 0, 0]}"#,
            r#"{"shape": {"ball": {"radius": 0.5}}, "position": [0.5, 0.5, 0]}"#,
        ],
    );
    let (status, err, events, stats) = run(&dir, &scene, &[]);
    assert_eq!(status, 0, "{err}");
    let want = "\
{\"t\": 0.0, \"a\": 0, \"b\": 3, \"kind\": \"begin\"}
{\"t\": 0.0, \"a\": 1, \"b\": 2, \"kind\": \"begin\"}
{\"t\": 1.3660254037844386, \"a\": 0, \"b\": 3, \"kind\": \"end\"}
{\"t\": 4.0, \"a\": 0, \"b\": 2, \"kind\": \"begin\"}
{\"t\": 5.0, \"a\": 0, \"b\": 1, \"kind\": \"begin\"}
{\"t\": 5.0, \"a\": 0, \"b\": 1, \"kind\": \"end\"}
{\"t\": 6.0, \"a\": 0, \"b\": 2, \"kind\": \"end\"}
";
    assert_eq!(events.unwrap(), want);
    let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
    // Four objects: the brute force's six pairs cost less than any structure.
    assert_eq!(stats["structure"], "brute-force");
    assert_eq!(stats["objects"], 4);
    assert_eq!(stats["contacts"]["begin"], 4);
    assert_eq!(stats["contacts"]["end"], 3);
    // Every pair a candidate.
    assert_eq!(stats["candidate_pairs"]["max"], 6);
    // The loose grid writes the same bytes, with fewer candidates.
    let (status, err, grid, stats) = run(&dir, &scene, &["--structure", "loose-grid"]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(grid.unwrap(), want);
    let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
    assert_eq!(stats["structure"], "loose-grid");
    assert!(stats["candidate_pairs"]["max"].as_u64().unwrap() < 6);
    assert!(stats["events"]["total"].as_u64().unwrap() >= 4);
    assert!(stats["wall_seconds"].as_f64().unwrap() >= 0.0);
}

#[test]
fn cuboids_and_hulls_in_a_free_world() {
    let dir = temp_dir("shapes");
    // A unit cube at rest; a tetrahedron falling onto it vertex first (its lowest vertex 1
    // below its origin), a ball flying through it along x, and a spinning cuboid far away.
    let scene = scene_with(
        r#""world": "free", "horizon": 10.0"#,
        &[
            r#"{"shape": {"cuboid": {"half_extents": [1, 1, 1]}}, "position": [0, 0, 0]}"#,
            r#"{"shape": {"convex_hull": {"points": [[0, 0, -1], [1, 0, 0.5], [-0.5, 0.8, 0.5], [-0.5, -0.8, 0.5]]}},
                "position": [0.2, 0.1, 7], "velocity": [0, 0, -2]}"#,
            r#"{"shape": {"ball": {"radius": 0.5}}, "position": [-9, 0.3, 0], "velocity": [2, 0, 0]}"#,
            r#"{"shape": {"cuboid": {"half_extents": [0.5, 2, 0.5]}}, "position": [100, 0, 0],
                "orientation": [0, 0, 0.3826834323650898, 0.9238795325112867], "angular_velocity": [0, 0, 3]}"#,
        ],
    );
    for structure in ["sweep", "brute-force"] {
        let (status, err, events, stats) = run(&dir, &scene, &["--structure", structure]);
        assert_eq!(status, 0, "{err}");
        // The tetrahedron's vertex reaches the cube's top (z = 1) at t = 2.5 and its top face
        // (z = 0.5 above the origin) leaves the cube's bottom (z = -1) at t = 4.25; the ball
        // touches x = -1 at t = 3.75 and leaves x = 1 at 5.25.
        // Times are the root finder's, within a few ulps of the exact ones.
        let want = [
            (2.5, 0, 1, "begin"),
            (3.75, 0, 2, "begin"),
            (4.25, 0, 1, "end"),
            (5.25, 0, 2, "end"),
        ];
        let log = events.unwrap();
        let lines: Vec<serde_json::Value> = log
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), want.len(), "{structure}: {log}");
        for (line, (t, a, b, kind)) in lines.iter().zip(want) {
            assert!(
                (line["t"].as_f64().unwrap() - t).abs() < 1e-12,
                "{structure}: {log}"
            );
            assert_eq!(
                (
                    line["a"].as_u64(),
                    line["b"].as_u64(),
                    line["kind"].as_str()
                ),
                (Some(a), Some(b), Some(kind)),
                "{structure}: {log}"
            );
        }
        let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
        assert_eq!(stats["structure"], structure);
    }
}

#[test]
fn elastic_plane_scene_with_walls() {
    let dir = temp_dir("elastic");
    let scene = scene_with(
        r#""world": "plane", "horizon": 10.0, "response": "elastic", "walls": {"min": [-10, -10, 0], "max": [10, 10, 0]}"#,
        &[
            r#"{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 0], "velocity": [1, 0, 0]}"#,
            r#"{"shape": {"ball": {"radius": 1}}, "position": [5, 0, 0]}"#,
        ],
    );
    let (status, err, events, stats) = run(&dir, &scene, &[]);
    assert_eq!(status, 0, "{err}");
    // Ball 0 hits ball 1 at t = 3; ball 1 moves on, bounces off x = 9 at t = 7, meets ball 0
    // (at rest, centre 3) when its tangency point is at 5: t = 7 + 4 = 11 > horizon.
    assert_eq!(
        events.unwrap(),
        "{\"t\": 3.0, \"a\": 0, \"b\": 1, \"kind\": \"begin\"}\n"
    );
    let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
    assert_eq!(stats["bounces"], 1);
}

#[test]
fn every_error_case_names_the_field_and_writes_nothing() {
    let free = r#""world": "free", "horizon": 10.0"#;
    let cases: Vec<(String, &str)> = vec![
        ("not json".into(), "not valid JSON"),
        (
            scene_with(r#""world": "free", "horizon": 10.0, "gravity": 1"#, &[BALL]),
            "gravity: unknown field",
        ),
        (r#"{"horizon": 1, "objects": []}"#.into(), "world: missing"),
        (
            r#"{"world": "free", "objects": []}"#.into(),
            "horizon: missing",
        ),
        (
            r#"{"world": "free", "horizon": 1}"#.into(),
            "objects: missing",
        ),
        (
            scene_with(r#""world": "space", "horizon": 1"#, &[]),
            "world: must be",
        ),
        (
            scene_with(r#""world": "free", "horizon": 0"#, &[]),
            "horizon: must be > 0",
        ),
        (
            scene_with(r#""world": "free", "horizon": -1"#, &[]),
            "horizon: must be > 0",
        ),
        (
            scene_with(r#""world": "free", "horizon": 1e999"#, &[]),
            "horizon: must be a finite number",
        ),
        (
            scene_with(r#""world": "free", "horizon": "10""#, &[]),
            "horizon: must be a number",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "sticky""#,
                &[],
            ),
            "response: must be",
        ),
        (
            scene_with(
                free,
                &[
                    BALL,
                    r#"{"shape": {"ball": {"radius": 0.5}}, "position": [0, 0, 0], "spin": 1}"#,
                ],
            ),
            "objects[1].spin: unknown field",
        ),
        (
            scene_with(free, &[r#"{"position": [0, 0, 0]}"#]),
            "objects[0].shape: missing",
        ),
        (
            scene_with(free, &[r#"{"shape": {"ball": {"radius": 1}}}"#]),
            "objects[0].position: missing",
        ),
        (
            scene_with(
                free,
                &[r#"{"shape": {"ball": {"radius": 1}}, "position": [0, 0]}"#],
            ),
            "objects[0].position: must be an array of 3",
        ),
        (
            scene_with(
                free,
                &[
                    BALL,
                    r#"{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 1e999]}"#,
                ],
            ),
            "objects[1].position[2]: must be a finite number",
        ),
        (
            scene_with(
                free,
                &[
                    r#"{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 0], "velocity": [0, null, 0]}"#,
                ],
            ),
            "objects[0].velocity[1]: must be a number",
        ),
        (
            scene_with(
                free,
                &[r#"{"shape": {"ball": {"radius": 0}}, "position": [0, 0, 0]}"#],
            ),
            "objects[0].shape.ball.radius: must be > 0",
        ),
        (
            scene_with(
                free,
                &[r#"{"shape": {"ball": {"radius": -2}}, "position": [0, 0, 0]}"#],
            ),
            "objects[0].shape.ball.radius: must be > 0",
        ),
        (
            scene_with(free, &[r#"{"shape": {"ball": {}}, "position": [0, 0, 0]}"#]),
            "objects[0].shape.ball.radius: missing",
        ),
        (
            scene_with(
                free,
                &[r#"{"shape": {"cuboid": {"half_extents": [1, 0, 1]}}, "position": [0, 0, 0]}"#],
            ),
            "objects[0].shape.cuboid.half_extents[1]: must be > 0",
        ),
        (
            scene_with(
                free,
                &[
                    r#"{"shape": {"convex_hull": {"points": [[0,0,0],[1,0,0],[0,1,0]]}}, "position": [0, 0, 0]}"#,
                ],
            ),
            "objects[0].shape.convex_hull.points: needs at least 4",
        ),
        (
            scene_with(
                free,
                &[
                    r#"{"shape": {"convex_hull": {"points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}}, "position": [0, 0, 0]}"#,
                ],
            ),
            "objects[0].shape.convex_hull.points: the points are coplanar",
        ),
        (
            scene_with(
                free,
                &[
                    r#"{"shape": {"ball": {"radius": 1}, "cuboid": {"half_extents": [1, 1, 1]}}, "position": [0, 0, 0]}"#,
                ],
            ),
            "objects[0].shape: must hold exactly one",
        ),
        (
            scene_with(
                free,
                &[r#"{"shape": {"sphere": {"radius": 1}}, "position": [0, 0, 0]}"#],
            ),
            "objects[0].shape.sphere: unknown field",
        ),
        (
            scene_with(
                free,
                &[
                    r#"{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 0], "orientation": [0, 0, 0, 2]}"#,
                ],
            ),
            "objects[0].orientation: must be a unit quaternion",
        ),
        (
            scene_with(
                r#""world": "plane", "horizon": 1"#,
                &[
                    BALL,
                    r#"{"shape": {"cuboid": {"half_extents": [1, 1, 1]}}, "position": [0, 0, 0]}"#,
                ],
            ),
            "objects[1].shape: a \"plane\" world holds balls only",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic""#,
                &[r#"{"shape": {"cuboid": {"half_extents": [1, 1, 1]}}, "position": [0, 0, 0]}"#],
            ),
            "objects[0].shape: the \"elastic\" response applies to balls only",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "walls": {"min": [0, 0, 0], "max": [1, 0, 1]}"#,
                &[],
            ),
            "walls.max[1]: must be greater",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "walls": {"min": [0, 0, 0]}"#,
                &[],
            ),
            "walls.max: missing",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic", "walls": {"min": [0, 0, 0], "max": [10, 10, 10]}"#,
                &[r#"{"shape": {"ball": {"radius": 1}}, "position": [5, 5, 9.5]}"#],
            ),
            "objects[0].position[2]: the ball (radius 1) starts outside the walls",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic", "periodic": {"min": [0, 0, 0], "max": [10, 10, 10]}, "walls": {"min": [0, 0, 0], "max": [10, 10, 10]}"#,
                &[],
            ),
            "periodic: cannot be combined with walls",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "periodic": {"min": [0, 0, 0], "max": [10, 10, 10]}"#,
                &[],
            ),
            "periodic: needs the \"elastic\" response",
        ),
        (
            scene_with(
                r#""world": "plane", "horizon": 1, "response": "elastic", "periodic": {"min": [0, 0, 0], "max": [10, 10, 10]}"#,
                &[],
            ),
            "periodic: applies to \"free\" worlds only",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic", "periodic": {"min": [0, 0, 0], "max": [10, 10, 0]}"#,
                &[],
            ),
            "periodic.max[2]: must be greater",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic", "periodic": {"min": [0, 0, 0], "max": [10, 10, 10]}"#,
                &[r#"{"shape": {"ball": {"radius": 1}}, "position": [5, 5, 11]}"#],
            ),
            "objects[0].position[2]: the centre starts outside the periodic box",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic", "periodic": {"min": [0, 0, 0], "max": [10, 10, 10]}"#,
                &[
                    r#"{"shape": {"ball": {"radius": 1}}, "position": [5, 5, 5], "acceleration": [0, 0, -1]}"#,
                ],
            ),
            "objects[0].acceleration: balls in a periodic box move linearly",
        ),
        (
            scene_with(
                r#""world": "free", "horizon": 1, "response": "elastic", "periodic": {"min": [0, 0, 0], "max": [5, 5, 5]}"#,
                &[r#"{"shape": {"ball": {"radius": 1}}, "position": [2, 2, 2]}"#],
            ),
            "periodic box: each side must be at least",
        ),
    ];
    let dir = temp_dir("errors");
    for (scene, expected) in &cases {
        let (status, err, events, stats) = run(&dir, scene, &[]);
        assert_eq!(status, 2, "scene {scene}: status {status}, stderr {err}");
        assert!(
            err.contains(expected),
            "scene {scene}: expected {expected:?} in {err:?}"
        );
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            events.is_none() && stats.is_none(),
            "scene {scene}: output written"
        );
    }
}

#[test]
fn bad_options_are_errors() {
    let dir = temp_dir("options");
    let scene = scene_with(r#""world": "free", "horizon": 1"#, &[BALL]);
    let (status, err, events, _) = run(&dir, &scene, &["--structure", "octree"]);
    assert_eq!(status, 2);
    assert!(
        err.contains("invalid value 'octree'") && err.contains("loose-grid"),
        "{err}"
    );
    assert!(events.is_none());
    let (status, err, _, _) = run(&dir, &scene, &["--structure", "rolling-tree"]);
    assert_eq!(status, 2);
    assert!(err.contains("\"plane\" worlds only"), "{err}");
    let missing = tool()
        .args(["run", "/nonexistent/scene.json"])
        .output()
        .unwrap();
    assert_eq!(missing.status.code(), Some(2));
    let (status, _, events, _) = run(&dir, &scene, &["--structure", "brute-force"]);
    assert_eq!(status, 0);
    assert!(events.is_some());
}

#[test]
fn same_scene_twice_gives_identical_bytes() {
    let dir = temp_dir("determinism");
    let scene = kinetic_scenes::BallScene::marbles_on_a_table()
        .build()
        .to_json();
    // The default races its shortlist, which timing decides: the log and the contacts do
    // not change; with a named structure nothing but the wall time does.
    let strip = |s: String, raced: bool| {
        let mut v: serde_json::Value = serde_json::from_str(&s).unwrap();
        let kept: &[&str] = if raced {
            &["contacts", "bounces", "objects", "horizon"]
        } else {
            &[]
        };
        let map = v.as_object_mut().unwrap();
        map.remove("wall_seconds");
        if raced {
            map.retain(|k, _| kept.contains(&k.as_str()));
        }
        v
    };
    for args in [&[][..], &["--structure", "loose-grid"][..]] {
        let (s1, _, e1, st1) = run(&dir, &scene, args);
        let (s2, _, e2, st2) = run(&dir, &scene, args);
        assert_eq!((s1, s2), (0, 0));
        let (e1, e2) = (e1.unwrap(), e2.unwrap());
        assert!(e1.lines().count() > 100);
        assert_eq!(e1, e2);
        let raced = args.is_empty();
        let (st1, st2) = (strip(st1.unwrap(), raced), strip(st2.unwrap(), raced));
        assert!(st1["contacts"]["begin"].as_u64().unwrap() > 100);
        assert_eq!(st1, st2, "{args:?}");
    }
}

#[test]
fn scene_round_trips_through_json() {
    let scene = kinetic_scenes::BallScene::marbles_on_a_table().build();
    let again = kinetic_collide::scene::Scene::from_json(&scene.to_json()).unwrap();
    assert_eq!(scene, again);
}

#[test]
fn plane_scenes_run_on_every_plane_structure_and_match_the_brute_force() {
    let dir = temp_dir("rolling");
    let mut params = kinetic_scenes::BallScene::marbles_on_a_table();
    params.n = 120;
    params.horizon = 10.0;
    let scene = params.build().to_json();
    let (status, err, chosen, stats) = run(&dir, &scene, &[]);
    assert_eq!(status, 0, "{err}");
    let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
    // Marbles of radii 1:50 start on the grid (and may race on from there).
    let first = stats["race"][0]["structure"].as_str();
    assert_eq!(
        first.unwrap_or(stats["structure"].as_str().unwrap()),
        "grid"
    );
    let chosen = chosen.unwrap();
    assert!(chosen.lines().count() > 20, "{chosen}");
    let (_, _, _, tree) = run(&dir, &scene, &["--structure", "rolling-tree"]);
    let tree: serde_json::Value = serde_json::from_str(&tree.unwrap()).unwrap();
    let boxes = tree["structure_stats"]["max_boxes_per_point"]
        .as_f64()
        .unwrap();
    assert!(boxes >= 1.0, "{tree}");
    for name in [
        "rolling-tree",
        "rolling-global-lists",
        "sweep",
        "grid",
        "brute-force",
    ] {
        let (status, err, events, stats) = run(&dir, &scene, &["--structure", name]);
        assert_eq!(status, 0, "{err}");
        let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
        assert_eq!(stats["structure"], name);
        // Every structure makes the same certificates for the same pair (they depend on the
        // flight plans only), so the logs are identical, byte for byte.
        assert_eq!(events.unwrap(), chosen, "{name}");
    }
}

#[test]
fn compare_scores_every_method_and_writes_csv_and_chart() {
    let dir = temp_dir("compare");
    // A bullets scene file beside two built-in families at small sizes.
    let scene = kinetic_scenes::families::Family::Bullets.scene(20, 2);
    let file = dir.join("bullets.json");
    std::fs::write(&file, scene.to_json()).unwrap();
    let out = tool()
        .arg("compare")
        .arg(&file)
        .args(["gas:30", "marbles:30", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let table = String::from_utf8_lossy(&out.stdout);
    let csv = std::fs::read_to_string(dir.join("compare.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // Free scenes: sweep, guards, grid, loose grid, brute force + 5 steps x (stepped, 3 rapier
    // variants, 3 avian variants); the plane scene: two rolling structures, sweep, grid, loose
    // grid, brute force + the same 35.
    assert_eq!(rows.len(), 40 + 40 + 41, "{csv}");
    assert!(csv.starts_with("scene,objects,method,default,step,wall_seconds,contacts,missed"));
    for r in &rows {
        // Kinetic rows (step "exact") miss nothing and report nothing false.
        if r[4] == "exact" {
            assert_eq!((r[7], r[11]), ("0", "0"), "{r:?}");
        }
    }
    // Each scene has exactly one default, a kinetic structure.
    for scene in ["bullets", "gas", "marbles"] {
        let defaults: Vec<_> = rows
            .iter()
            .filter(|r| r[0] == scene && r[3] == "true")
            .collect();
        assert_eq!(defaults.len(), 1, "{scene}: {defaults:?}");
        assert_eq!(defaults[0][4], "exact");
    }
    // The bullets tunnel through the plates at 1/60 without CCD; rapier's CCD sees them.
    let missed = |method: &str, step: &str| -> usize {
        let r = rows
            .iter()
            .find(|r| r[0] == "bullets" && r[2] == method && r[4] == step)
            .unwrap();
        r[7].parse().unwrap()
    };
    assert!(missed("stepped", "1/60") > 0);
    assert!(missed("rapier", "1/60") > 0);
    assert_eq!(missed("rapier+ccd", "1/60"), 0);
    // avian's CCD skips sensors, so it sees no more than avian without it; the kinetic plugin
    // hands the engine the same pairs.
    assert!(missed("avian", "1/60") > 0);
    assert_eq!(missed("avian+ccd", "1/60"), missed("avian", "1/60"));
    assert_eq!(missed("avian+kinetic", "1/60"), missed("avian", "1/60"));
    assert!(table.contains("| bullets (28) | sweep"), "{table}");
    assert!(table.contains(" (default) | exact |"), "{table}");
    let png = std::fs::read(dir.join("compare.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // A name that is neither a file, a family nor a case: status 2, naming it.
    let bad = tool().args(["compare", "plasma"]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("plasma"));
}

#[test]
fn generate_writes_hard_spheres_that_run_on_the_cell_grid() {
    let dir = temp_dir("generate");
    let path = dir.join("mixture.json");
    let generate = || {
        let mut cmd = tool();
        cmd.args([
            "generate",
            "--n",
            "300",
            "--ratio",
            "0.3",
            "--collisions",
            "2000",
        ]);
        cmd
    };
    let out = generate().arg("-o").arg(&path).output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = kinetic_collide::scene::Scene::from_json(&text).unwrap();
    assert_eq!(scene.objects.len(), 300);
    assert_eq!(scene.response, kinetic_collide::Response::Elastic);
    assert!(scene.walls.is_some());
    let (status, err, events, stats) = run(&dir, &text, &[]);
    assert_eq!(status, 0, "{err}");
    let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
    assert_eq!(stats["structure"], "cells");
    let events = events.unwrap();
    assert!(events.lines().count() > 1000);
    assert!(events.lines().all(|l| l.ends_with(r#""kind": "begin"}"#)));
    // The world with the kinetic grid logs the same bytes.
    let (_, _, grid, _) = run(&dir, &text, &["--structure", "grid"]);
    assert_eq!(grid.unwrap(), events);
    // Same seed, same scene; bad parameters are named, with status 2 and no file.
    let again = generate().output().unwrap();
    assert_eq!(String::from_utf8_lossy(&again.stdout), text);
    let bad = dir.join("bad.json");
    for (flag, value, name) in [("--ratio", "1.5", "ratio"), ("--packing", "0.6", "packing")] {
        let out = tool()
            .args(["generate", flag, value, "-o"])
            .arg(&bad)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains(name));
        assert!(!bad.exists());
    }
}

#[test]
fn generate_periodic_dense_fluids_that_report_the_bulk() {
    let dir = temp_dir("periodic");
    let out = tool()
        .args([
            "generate",
            "--n",
            "500",
            "--packing",
            "0.45",
            "--periodic",
            "--collisions",
            "20000",
        ])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let scene = kinetic_collide::scene::Scene::from_json(&text).unwrap();
    assert!(scene.periodic.is_some() && scene.walls.is_none());
    assert_eq!(
        kinetic_collide::scene::Scene::from_json(&scene.to_json()).unwrap(),
        scene
    );
    let (status, err, events, stats) = run(&dir, &text, &[]);
    assert_eq!(status, 0, "{err}");
    let stats: serde_json::Value = serde_json::from_str(&stats.unwrap()).unwrap();
    assert_eq!(stats["structure"], "periodic");
    let bulk = &stats["bulk"];
    for key in [
        "collision_rate",
        "pressure",
        "compressibility",
        "temperature",
        "packing",
    ] {
        assert!(bulk[key].as_f64().is_some_and(|v| v > 0.0), "{key}: {bulk}");
    }
    assert!((bulk["packing"].as_f64().unwrap() - 0.45).abs() < 1e-9);
    assert!(events.unwrap().lines().count() > 10_000);
    // The other structures do not wrap: naming one is an error, and so are frames.
    for extra in [&["--structure", "grid"][..], &["--frames", "2"][..]] {
        let (status, err, events, _) = run(&dir, &text, extra);
        assert_eq!(status, 2, "{extra:?}: {err}");
        assert!(err.contains("periodic"), "{err}");
        assert!(events.is_none());
    }
}

#[test]
fn run_help_names_every_structure() {
    let out = tool().args(["run", "--help"]).output().expect("runs");
    assert!(out.status.success());
    // clap wraps the help text: compare with the line breaks taken out.
    let help = String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    for name in kinetic_collide::Structure::ALL.map(kinetic_collide::Structure::name) {
        assert!(
            help.contains(name),
            "`run --help` does not name {name}: {help}"
        );
    }
}
