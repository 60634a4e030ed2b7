//! Measuring whole processes for the side-by-side benches: peak resident memory of this
//! process, and of a child run under GNU time.

use std::process::Command;

/// Peak resident memory of this process, in KiB (`VmHWM`), or NaN where the system does not
/// say.
pub fn peak_kb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        })
        .unwrap_or(f64::NAN)
}

/// A child run under `/usr/bin/time`: its standard output, peak KiB and wall seconds.
pub struct Timed {
    /// What it printed.
    pub stdout: String,
    /// Peak resident memory, KiB.
    pub peak_kb: f64,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Runs `program` with `args` in `dir` under GNU time (`/usr/bin/time`).
pub fn timed(
    dir: &std::path::Path,
    program: &std::path::Path,
    args: &[&str],
) -> Result<Timed, String> {
    let out = Command::new("/usr/bin/time")
        .current_dir(dir)
        .args(["-f", "PEAK_KB=%M SECONDS=%e"])
        .arg(program)
        .args(args)
        .output()
        .map_err(|e| format!("/usr/bin/time: {e}"))?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!("{} failed: {stderr}", program.display()));
    }
    let field = |name: &str| {
        stderr
            .split_whitespace()
            .rev()
            .find_map(|w| w.strip_prefix(name))
            .and_then(|v| v.parse().ok())
            .unwrap_or(f64::NAN)
    };
    Ok(Timed {
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        peak_kb: field("PEAK_KB="),
        seconds: field("SECONDS="),
    })
}

/// A bench's child run: when `args` hold `--child SYSTEM COUNT`, runs `run` on the parsed
/// system and count, and exits with status 1 and the message if it fails. Returns whether
/// this was a child run (the bench's `main` then returns).
pub fn run_child<S>(
    args: &[String],
    parse: impl Fn(&str) -> Result<S, String>,
    run: impl Fn(S, f64) -> Result<(), String>,
) -> bool {
    let Some(i) = args.iter().position(|a| a == "--child") else {
        return false;
    };
    let field = |k: usize| args.get(i + k).map(String::as_str).unwrap_or_default();
    let result = parse(field(1)).and_then(|s| {
        let count = field(2)
            .parse()
            .map_err(|e| format!("--child count: {e}"))?;
        run(s, count)
    });
    if let Err(e) = result {
        eprintln!("{e}");
        std::process::exit(1);
    }
    true
}
