//! The command-line tool against hostile but fair use: magnitudes that overflow, closed
//! pipes, full disks, outputs that would clobber the input or each other, links, pipes and
//! devices as outputs, folders, signals in the middle of a long run. Each test runs the
//! binary as a user would.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

fn tool() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kinetic-collide"))
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "kinetic-collide-hostile-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

const TWO_BALLS: &str = r#"{"world": "free", "horizon": 10, "objects": [
  {"shape": {"ball": {"radius": 0.5}}, "position": [0, 0, 0], "velocity": [1, 0, 0]},
  {"shape": {"ball": {"radius": 0.5}}, "position": [5, 0, 0]}]}"#;

const TWO_BALLS_LOG: &str = "{\"t\": 4.0, \"a\": 0, \"b\": 1, \"kind\": \"begin\"}\n\
                             {\"t\": 6.0, \"a\": 0, \"b\": 1, \"kind\": \"end\"}\n";

/// Writes a hard-sphere gas of `n` spheres running for about `collisions` collisions.
fn gas(dir: &Path, n: usize, collisions: f64) -> PathBuf {
    let path = dir.join(format!("gas-{n}-{collisions}.json"));
    let out = tool()
        .args(["generate", "--n", &n.to_string(), "--collisions"])
        .arg(collisions.to_string())
        .arg("--out")
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    path
}

fn run_status(args: &[&str], dir: &Path) -> (i32, String) {
    let out = tool().args(args).current_dir(dir).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn magnitudes_that_overflow_are_refused_with_status_2() {
    let dir = temp_dir("overflow");
    let cases = [
        // A plane-world ball of radius 1e155 once panicked in the rolling tree's build.
        r#"{"world": "plane", "horizon": 10, "objects": [{"shape": {"ball": {"radius": 1e155}}, "position": [0, 0, 0]}]}"#,
        r#"{"world": "free", "horizon": 10, "objects": [{"shape": {"ball": {"radius": 1e154}}, "position": [0, 0, 0]}, {"shape": {"ball": {"radius": 1e154}}, "position": [1e155, 0, 0], "velocity": [-1e154, 0, 0]}]}"#,
        r#"{"world": "free", "horizon": 10, "objects": [{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 0], "velocity": [1e154, 0, 0]}]}"#,
        r#"{"world": "free", "horizon": 10, "objects": [{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 0], "acceleration": [1e300, 0, 0]}]}"#,
        r#"{"world": "free", "horizon": 1, "objects": [{"shape": {"ball": {"radius": 1}}, "position": [0, 0, 0], "velocity": [1.7e308, 0, 0]}, {"shape": {"ball": {"radius": 1}}, "position": [10, 0, 0], "velocity": [-1.7e308, 0, 0]}]}"#,
        r#"{"world": "free", "horizon": 1, "objects": [{"shape": {"cuboid": {"half_extents": [1e300, 1, 1]}}, "position": [0, 0, 0]}]}"#,
        r#"{"world": "free", "horizon": 1e300, "objects": [{"shape": {"ball": {"radius": 0.5}}, "position": [0, 0, 0], "velocity": [1, 0, 0]}, {"shape": {"ball": {"radius": 0.5}}, "position": [5, 0, 0], "velocity": [2, 0, 0]}]}"#,
    ];
    for (k, scene) in cases.iter().enumerate() {
        std::fs::write(dir.join("s.json"), scene).unwrap();
        let (code, err) = run_status(&["run", "s.json", "--events", "e.jsonl"], &dir);
        assert_eq!(code, 2, "case {k}: {err}");
        assert!(
            err.contains("objects[") && err.contains("beyond"),
            "case {k}: {err}"
        );
        assert!(!dir.join("e.jsonl").exists(), "case {k}");
    }
}

#[test]
fn a_closed_pipe_ends_the_run_quietly_and_the_stats_are_written() {
    let dir = temp_dir("pipe");
    let scene = gas(&dir, 300, 3e4);
    let stats = dir.join("stats.json");
    let mut child = tool()
        .arg("run")
        .arg(&scene)
        .arg("--stats")
        .arg(&stats)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read one line, then close the pipe.
    let mut stdout = child.stdout.take().unwrap();
    let mut first = [0u8; 16];
    stdout.read_exact(&mut first).unwrap();
    drop(stdout);
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    let stats = std::fs::read_to_string(&stats).unwrap();
    assert!(stats.contains("\"interrupted\""), "{stats}");

    // `generate | head -c 16`.
    let mut child = tool()
        .args(["generate", "--n", "3000"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    stdout.read_exact(&mut first).unwrap();
    drop(stdout);
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn a_full_disk_is_a_clear_error_and_leaves_nothing_behind() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full on this system: the full-disk case is not exercised here");
        return;
    }
    let dir = temp_dir("full");
    std::fs::write(dir.join("s.json"), TWO_BALLS).unwrap();
    let (code, err) = run_status(&["run", "s.json", "--events", "/dev/full"], &dir);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("/dev/full") && err.contains("space"), "{err}");
    assert_eq!(listing(&dir), ["s.json"]);
}

#[test]
fn generate_takes_any_ratio_in_its_range() {
    let dir = temp_dir("ratio");
    for ratio in ["1e-3", "1e-6"] {
        let out = dir.join(format!("mix{ratio}.json"));
        let (code, err) = run_status(
            &[
                "generate",
                "--n",
                "100",
                "--ratio",
                ratio,
                "--out",
                out.to_str().unwrap(),
            ],
            &dir,
        );
        assert_eq!(code, 0, "{ratio}: {err}");
        let text = std::fs::read_to_string(&out).unwrap();
        let scene = kinetic_collide::scene::Scene::from_json(&text).unwrap();
        assert_eq!(scene.objects.len(), 100);
    }
    // Spheres too small for f64's arithmetic: refused, not written.
    let (code, err) = run_status(
        &[
            "generate", "--n", "100", "--ratio", "1e-300", "--out", "x.json",
        ],
        &dir,
    );
    assert_eq!(code, 2, "{err}");
    assert!(!dir.join("x.json").exists());
}

#[test]
fn outputs_never_clobber_the_input_or_each_other() {
    let dir = temp_dir("clobber");
    std::fs::write(dir.join("in.json"), TWO_BALLS).unwrap();
    for args in [
        &["run", "in.json", "--events", "in.json"][..],
        &["run", "in.json", "--stats", "in.json"],
        &["run", "in.json", "--events", "./in.json"],
        &["run", "in.json", "--events", "x", "--stats", "x"],
        &["run", "in.json", "--stats", "-"],
        &["run", "in.json", "--events", "adir"],
    ] {
        std::fs::create_dir_all(dir.join("adir")).unwrap();
        let (code, err) = run_status(args, &dir);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(
            std::fs::read_to_string(dir.join("in.json")).unwrap(),
            TWO_BALLS
        );
        assert_eq!(listing(&dir), ["adir", "in.json"], "{args:?}");
    }
    // A link to the input is the input.
    std::os::unix::fs::symlink("in.json", dir.join("link")).unwrap();
    let (code, err) = run_status(&["run", "in.json", "--events", "link"], &dir);
    assert_eq!(code, 2, "{err}");
    assert_eq!(
        std::fs::read_to_string(dir.join("in.json")).unwrap(),
        TWO_BALLS
    );
}

#[test]
fn links_pipes_and_devices_are_written_through() {
    let dir = temp_dir("through");
    std::fs::write(dir.join("s.json"), TWO_BALLS).unwrap();
    // A link (to a file not there yet, then to the file): the link stays a link.
    std::os::unix::fs::symlink("log.jsonl", dir.join("link")).unwrap();
    for _ in 0..2 {
        let (code, err) = run_status(&["run", "s.json", "--events", "link"], &dir);
        assert_eq!(code, 0, "{err}");
        assert!(
            std::fs::symlink_metadata(dir.join("link"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(
            std::fs::read_to_string(dir.join("log.jsonl")).unwrap(),
            TWO_BALLS_LOG
        );
    }
    // /dev/null stays a device.
    let (code, err) = run_status(&["run", "s.json", "--events", "/dev/null"], &dir);
    assert_eq!(code, 0, "{err}");
    assert!(!std::fs::metadata("/dev/null").unwrap().is_file());
    // A FIFO gets the log and stays a FIFO.
    let fifo = dir.join("fifo");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        let (code, err) = run_status(&["run", "s.json", "--events", "fifo"], &dir);
        assert_eq!(code, 0, "{err}");
        assert_eq!(reader.join().unwrap(), TWO_BALLS_LOG);
        assert!(!std::fs::metadata(&fifo).unwrap().is_file());
    }
    // `-` is standard output, and `run -` reads standard input.
    let mut child = tool()
        .args(["run", "-", "--events", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(TWO_BALLS.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), TWO_BALLS_LOG);
    let mut names = listing(&dir);
    names.retain(|n| n != "fifo");
    assert_eq!(names, ["link", "log.jsonl", "s.json"]);
}

#[test]
fn an_interrupted_run_leaves_every_event_up_to_the_interrupt() {
    let dir = temp_dir("interrupt");
    let scene = gas(&dir, 2000, 1e10);
    let (events, stats) = (dir.join("events.jsonl"), dir.join("stats.json"));
    for signal in ["INT", "TERM"] {
        let child = tool()
            .arg("run")
            .arg(&scene)
            .arg("--events")
            .arg(&events)
            .arg("--stats")
            .arg(&stats)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        let killed = Command::new("kill")
            .arg(format!("-{signal}"))
            .arg(child.id().to_string())
            .status()
            .unwrap();
        assert!(killed.success());
        let out = child.wait_with_output().unwrap();
        assert_eq!(
            out.status.code(),
            Some(130),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let log = std::fs::read_to_string(&events).unwrap();
        let mut last = 0.0f64;
        let mut lines = 0;
        for line in log.lines() {
            let v: serde_json::Value = serde_json::from_str(line).expect("a whole JSON line");
            let t = v["t"].as_f64().unwrap();
            assert!(t >= last);
            last = t;
            lines += 1;
        }
        assert!(log.ends_with('\n'));
        assert!(lines > 1000, "{lines} events in 1.5 s");
        let stats: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        let at = stats["interrupted"]["time"].as_f64().unwrap();
        // The log's times have ten decimals.
        assert!(
            at >= last - 1e-10 * last.max(1.0) && at - last < 1.0,
            "interrupted at {at}, last event at {last}"
        );
        assert_eq!(stats["contacts"]["begin"].as_u64().unwrap(), lines as u64);
        let mut names = listing(&dir);
        names.retain(|n| !n.starts_with("gas-"));
        assert_eq!(names, ["events.jsonl", "stats.json"], "no hidden file left");
    }
}

#[test]
fn syntax_errors_say_what_is_wrong() {
    let dir = temp_dir("syntax");
    for (text, want) in [
        ("", "empty"),
        ("{\"world\": ", "not valid JSON"),
        ("{\"horizon\": NaN}", "NaN and Infinity"),
        ("[1, 2]", "must be a JSON object"),
    ] {
        std::fs::write(dir.join("s.json"), text).unwrap();
        let (code, err) = run_status(&["run", "s.json"], &dir);
        assert_eq!(code, 2, "{text:?}");
        assert!(err.contains(want), "{text:?}: {err}");
        if want != "NaN and Infinity" {
            assert!(!err.contains("finite"), "{text:?}: {err}");
        }
    }
    // A byte-order mark is skipped.
    std::fs::write(dir.join("s.json"), format!("\u{feff}{TWO_BALLS}")).unwrap();
    let out = tool()
        .args(["run", "s.json"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), TWO_BALLS_LOG);
}

#[test]
fn a_second_signal_exits_at_once_and_leaves_no_partial_file() {
    let dir = temp_dir("twice");
    // A brute force over 6,000 spheres builds 1.8e7 certificates before its first event:
    // the first signal waits for an instant, the second does not.
    let scene = gas(&dir, 6000, 1e6);
    let events = dir.join("events.jsonl");
    let child = tool()
        .arg("run")
        .arg(&scene)
        .args(["--structure", "brute-force", "--events"])
        .arg(&events)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let kill = || {
        Command::new("kill")
            .arg("-INT")
            .arg(child.id().to_string())
            .status()
            .unwrap()
    };
    assert!(kill().success());
    std::thread::sleep(Duration::from_millis(100));
    let second = std::time::Instant::now();
    let _ = kill();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130));
    assert!(
        second.elapsed() < Duration::from_secs(2),
        "{:?}",
        second.elapsed()
    );
    let mut names = listing(&dir);
    names.retain(|n| !n.starts_with("gas-"));
    assert!(
        names.is_empty() || names == ["events.jsonl"],
        "no hidden file left: {names:?}"
    );
}

#[test]
fn no_structure_does_work_for_empty_space() {
    let dir = temp_dir("empty");
    // Two balls flying apart for 1e100 time units: nothing ever happens.
    let scene = r#"{"world": "free", "horizon": 1e100, "objects": [
      {"shape": {"ball": {"radius": 0.5}}, "position": [0, 0, 0], "velocity": [-1, 0.5, 0]},
      {"shape": {"ball": {"radius": 0.5}}, "position": [5, 0, 0], "velocity": [1, 0.25, 0]}]}"#;
    std::fs::write(dir.join("s.json"), scene).unwrap();
    for structure in ["sweep", "grid", "loose-grid", "guards", "brute-force", ""] {
        let mut args = vec!["run", "s.json", "--stats", "st.json"];
        if !structure.is_empty() {
            args.extend(["--structure", structure]);
        }
        let (code, err) = run_status(&args, &dir);
        assert_eq!(code, 0, "{structure}: {err}");
        let stats: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("st.json")).unwrap()).unwrap();
        let events = stats["events"]["total"].as_u64().unwrap();
        assert!(
            events < 5000,
            "{structure}: {events} events for two balls apart"
        );
    }
}

#[test]
fn endless_or_huge_inputs_are_refused_at_once() {
    let dir = temp_dir("endless");
    // A device that never ends: the first byte cannot begin a scene.
    let (code, err) = run_status(&["run", "/dev/zero"], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot begin a scene"), "{err}");
    // The same on standard input.
    let out = tool()
        .args(["run", "-"])
        .stdin(std::fs::File::open("/dev/zero").unwrap())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    // A trillion spheres: refused, naming the limit, nothing written.
    let (code, err) = run_status(
        &["generate", "--n", "1000000000000", "--out", "huge.json"],
        &dir,
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("at most 100,000,000"), "{err}");
    assert!(!dir.join("huge.json").exists());
}

#[test]
fn events_none_writes_the_statistics_only() {
    let dir = temp_dir("events-none");
    std::fs::write(dir.join("two.json"), TWO_BALLS).unwrap();
    let out = tool()
        .args([
            "run",
            "two.json",
            "--events",
            "none",
            "--stats",
            "stats.json",
        ])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    assert!(!dir.join("none").exists());
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("stats.json")).unwrap()).unwrap();
    assert_eq!(stats["contacts"]["begin"], 1);
    assert_eq!(stats["contacts"]["end"], 1);
}

#[test]
fn times_keep_every_digit() {
    let dir = temp_dir("digits");
    // Contact 4.5e-11 after the start: ten fixed decimals would write 0.
    let scene = r#"{"world": "free", "horizon": 1e-9, "objects": [
      {"shape": {"ball": {"radius": 0.5}}, "position": [0, 0, 0], "velocity": [1, 0, 0]},
      {"shape": {"ball": {"radius": 0.5}}, "position": [1.000000000045, 0, 0]}]}"#;
    std::fs::write(dir.join("close.json"), scene).unwrap();
    let out = tool()
        .args(["run", "close.json"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let log = String::from_utf8(out.stdout).unwrap();
    let line: serde_json::Value = serde_json::from_str(log.lines().next().unwrap()).unwrap();
    let t = line["t"].as_f64().unwrap();
    assert!((t - 4.5e-11).abs() < 1e-15, "{log}");
    // Written so that it reads back as the same double: the shortest such decimal.
    let written = log
        .split("\"t\": ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap();
    assert_eq!(written, format!("{t:?}"));
    assert_eq!(written.parse::<f64>().unwrap(), t);
}
