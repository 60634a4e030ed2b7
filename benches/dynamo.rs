//! Hard-sphere systems, kinetic-collide against DynamO, side by side in one run.
//!
//! ```text
//! cargo bench --bench dynamo -- [--dynamo DIR] [--collisions C] [--systems LIST] [--out FILE]
//! ```
//!
//! For each system (`gas:N` or `mix:RATIO:N`, default: the gas at 4000, 32000 and 256000, the
//! mixtures 0.5, 0.2 and 0.1 at 32000) it generates the scene (`kinetic-collide generate`'s
//! generator, seed 1), runs it on the chosen structure in a fresh process (the tool's `run`
//! minus file output: the event log is formatted as it goes and dropped), and reports
//! collisions per second, the process's peak memory per sphere, and the wall time for `C`
//! collisions (default 1e6).
//!
//! DynamO: pass `--dynamo DIR` with `DIR/dynamod` and `DIR/dynarun` built from its public
//! source (nothing of it is in this repository). DynamO makes the same system (its own
//! periodic box: `dynamod` places and equilibrates it), runs it for the same number of
//! collisions (fewer, and the time scaled, where it would take more than `--dynamo-budget`
//! seconds, default 120) and is timed the same way. Without DynamO the table holds our
//! figures only.

use kinetic_collide::hard_spheres::HardSpheres;
use kinetic_collide::run::{StructureName, choose_structure};
use kinetic_collide::scene::outer_radius;
use kinetic_collide::{ContactKind, ElasticCells, Walls};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// A system: size ratio (1 for the gas) and number of spheres.
#[derive(Clone, Copy, Debug)]
struct System {
    ratio: f64,
    n: usize,
}

impl System {
    fn parse(text: &str) -> Result<System, String> {
        let parts: Vec<&str> = text.split(':').collect();
        let num = |s: &str| s.parse::<f64>().map_err(|e| format!("{text}: {e}"));
        match parts.as_slice() {
            ["gas", n] => Ok(System {
                ratio: 1.0,
                n: num(n)? as usize,
            }),
            ["mix", r, n] => Ok(System {
                ratio: num(r)?,
                n: num(n)? as usize,
            }),
            _ => Err(format!("{text}: expected gas:N or mix:RATIO:N")),
        }
    }

    fn name(&self) -> String {
        if self.ratio == 1.0 {
            format!("gas:{}", self.n)
        } else {
            format!("mix:{}:{}", self.ratio, self.n)
        }
    }

    fn spheres(&self, collisions: f64) -> HardSpheres {
        HardSpheres {
            collisions,
            ..HardSpheres::mixture(self.n, self.ratio)
        }
    }
}

/// One measured run.
#[derive(Clone, Copy, Debug, Default)]
struct Measured {
    collisions: f64,
    seconds: f64,
    peak_kb: f64,
}

impl Measured {
    fn rate(&self) -> f64 {
        self.collisions / self.seconds
    }
}

/// Peak resident memory of this process, in KiB.
fn peak_kb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        })
        .unwrap_or(f64::NAN)
}

/// The child: runs one system and prints `collisions seconds peak_kb`.
fn child(system: System, collisions: f64) -> Result<(), String> {
    let scene = system
        .spheres(collisions)
        .build()
        .map_err(|e| e.to_string())?;
    if choose_structure(&scene) != StructureName::Cells {
        return Err(format!("{}: not run on the cell grid", system.name()));
    }
    let balls: Vec<_> = scene
        .objects
        .iter()
        .map(|o| (outer_radius(&o.shape), o.plan()))
        .collect();
    let walls: Walls = scene.walls.ok_or("no walls")?;
    let start = Instant::now();
    let mut cells = ElasticCells::new(walls, &balls).map_err(|e| e.to_string())?;
    let mut log = String::new();
    let mut sink = std::io::sink();
    let chunks = 100;
    let mut begun = 0u64;
    for k in 1..=chunks {
        cells
            .advance_to(scene.horizon * k as f64 / chunks as f64)
            .map_err(|e| e.to_string())?;
        log.clear();
        for e in cells.drain_events() {
            begun += u64::from(e.kind == ContactKind::Begin);
            let _ = writeln!(
                log,
                "{{\"t\": {:.10}, \"a\": {}, \"b\": {}, \"kind\": \"begin\"}}",
                e.time + 0.0,
                e.a.0,
                e.b.0
            );
        }
        let _ = sink.write_all(log.as_bytes());
    }
    let seconds = start.elapsed().as_secs_f64();
    println!("{begun} {seconds} {}", peak_kb());
    Ok(())
}

fn ours(system: System, collisions: f64) -> Result<Measured, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe)
        .args(["--child", &system.name(), &collisions.to_string()])
        .output()
        .map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let v: Vec<f64> = text
        .split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect();
    match v.as_slice() {
        [c, s, m] => Ok(Measured {
            collisions: *c,
            seconds: *s,
            peak_kb: *m,
        }),
        _ => Err(format!("child printed {text:?}")),
    }
}

/// Runs `cmd` under GNU time: wall seconds and peak KiB, or why not.
fn timed(cmd: &mut Command) -> Result<(f64, f64, String), String> {
    let start = Instant::now();
    let out = cmd.output().map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    if !out.status.success() {
        return Err(format!("{cmd:?} failed: {stderr}"));
    }
    let peak = stderr
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("PEAK_KB="))
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    Ok((
        seconds,
        peak,
        String::from_utf8_lossy(&out.stdout).into_owned(),
    ))
}

/// DynamO on the same system: `dynamod` makes it (periodic box, same N, packing fraction
/// and size ratio), `dynarun` equilibrates it, then runs it for the collisions counted.
fn dynamo(dir: &Path, system: System, collisions: f64, budget: f64) -> Result<Measured, String> {
    let work = std::env::temp_dir().join(format!("kinetic-dynamo-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let h = system.spheres(collisions);
    let species = h.species();
    let n = system.n;
    let packing = h.packing;
    let config = work.join("config.start.xml.bz2");
    let equilibrated = work.join("config.equilibrated.xml.bz2");
    let mut make = Command::new(dir.join("dynamod"));
    make.current_dir(&work);
    if species.len() == 1 {
        // FCC: 4 C^3 spheres; C chosen so that 4 C^3 is N.
        let c = ((n as f64 / 4.0).cbrt()).round() as usize;
        if 4 * c * c * c != n {
            return Err(format!("{n} is not 4 C^3 for DynamO's FCC lattice"));
        }
        let density = packing * 6.0 / std::f64::consts::PI;
        make.args(["-m", "0", "-C", &c.to_string(), "-d", &density.to_string()]);
    } else {
        return Err(dynamo_mixture_unsupported(&species));
    }
    make.arg("-o").arg(&config);
    timed(&mut make)?;
    // Equilibrate: 20 collisions per sphere.
    let mut eq = Command::new(dir.join("dynarun"));
    eq.current_dir(&work)
        .arg(&config)
        .args(["-c", &(20 * n).to_string(), "-o"])
        .arg(&equilibrated);
    timed(&mut eq)?;
    // A short run to size the measured one within the budget.
    let probe = 20_000.0f64.min(collisions);
    let (s, _, _) = dynarun(dir, &work, &equilibrated, probe)?;
    let count = collisions.min((budget / s * probe).max(probe)).round();
    let (seconds, peak_kb, _) = dynarun(dir, &work, &equilibrated, count)?;
    let _ = std::fs::remove_dir_all(&work);
    Ok(Measured {
        collisions: count,
        seconds,
        peak_kb,
    })
}

fn dynamo_mixture_unsupported(_species: &[kinetic_collide::hard_spheres::Species]) -> String {
    "mixtures: not set up for DynamO yet".to_string()
}

fn dynarun(
    dir: &Path,
    work: &Path,
    config: &Path,
    count: f64,
) -> Result<(f64, f64, String), String> {
    let mut cmd = Command::new("/usr/bin/time");
    cmd.current_dir(work)
        .args(["-f", "PEAK_KB=%M"])
        .arg(dir.join("dynarun"))
        .arg(config)
        .args(["-c", &format!("{count}"), "-o"])
        .arg(work.join("config.end.xml.bz2"))
        .arg("--out-data-file")
        .arg(work.join("output.xml.bz2"));
    timed(&mut cmd)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--child") {
        let result = System::parse(&args[i + 1])
            .and_then(|s| child(s, args[i + 2].parse().map_err(|e| format!("{e}"))?));
        if let Err(e) = result {
            eprintln!("{e}");
            std::process::exit(1);
        }
        return;
    }
    let mut dynamo_dir: Option<PathBuf> = None;
    let mut collisions = 1e6;
    let mut budget = 120.0;
    let mut out = PathBuf::from("target/dynamo-bench.md");
    let mut systems: Vec<System> = [
        "gas:4000",
        "gas:32000",
        "gas:256000",
        "mix:0.5:32000",
        "mix:0.2:32000",
        "mix:0.1:32000",
    ]
    .iter()
    .map(|s| System::parse(s).expect("a default system"))
    .collect();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().cloned().unwrap_or_default();
        match a.as_str() {
            "--dynamo" => dynamo_dir = Some(PathBuf::from(value())),
            "--collisions" => collisions = value().parse().expect("--collisions: a number"),
            "--dynamo-budget" => budget = value().parse().expect("--dynamo-budget: seconds"),
            "--out" => out = PathBuf::from(value()),
            "--systems" => {
                systems = value()
                    .split(',')
                    .map(|s| System::parse(s).unwrap_or_else(|e| panic!("--systems: {e}")))
                    .collect()
            }
            "--bench" => {}
            other => panic!("unknown argument {other}"),
        }
    }
    let mut table = String::from(
        "| system | spheres | kinetic-collide collisions/s | memory/sphere | time for 1e6 | \
         DynamO collisions/s | memory/sphere | time for 1e6 | ratio |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for system in systems {
        let name = system.name();
        eprintln!("{name}: kinetic-collide ...");
        let k = match ours(system, collisions) {
            Ok(k) => k,
            Err(e) => {
                eprintln!("{name}: {e}");
                continue;
            }
        };
        let n = system.n as f64;
        let mut row = format!(
            "| {name} | {} | {:.0} | {:.0} B | {:.2} s |",
            system.n,
            k.rate(),
            k.peak_kb * 1024.0 / n,
            1e6 / k.rate()
        );
        match dynamo_dir.as_deref().map(|d| {
            eprintln!("{name}: DynamO ...");
            dynamo(d, system, collisions, budget)
        }) {
            Some(Ok(d)) => {
                let _ = write!(
                    row,
                    " {:.0} | {:.0} B | {:.2} s{} | {:.1}x |",
                    d.rate(),
                    d.peak_kb * 1024.0 / n,
                    1e6 / d.rate(),
                    if d.collisions < 1e6 { " (scaled)" } else { "" },
                    k.rate() / d.rate()
                );
            }
            Some(Err(e)) => {
                eprintln!("{name}: DynamO: {e}");
                row.push_str(" - | - | - | - |");
            }
            None => row.push_str(" - | - | - | - |"),
        }
        eprintln!("{row}");
        table.push_str(&row);
        table.push('\n');
    }
    print!("{table}");
    if let Err(e) = std::fs::write(&out, &table) {
        eprintln!("{}: {e}", out.display());
    }
}
