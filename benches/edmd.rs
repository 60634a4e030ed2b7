//! Hard spheres in a periodic box, kinetic-collide against EDMD, side by side in one run.
//!
//! ```text
//! cargo bench --bench edmd -- [--edmd DIR] [--systems N:PACKING,...] [--collisions C]
//!                              [--repeat K] [--out FILE] [--tool PATH [--walls]]
//! ```
//!
//! For each system (default `32000:0.26,32000:0.45`) it runs EDMD (Smallenburg's
//! event-driven MD, single-core variant) and the periodic structure one after the other,
//! `K` times each (default 3), interleaved, and keeps each side's median run.
//!
//! - EDMD: built from its sources in `DIR` (`--edmd DIR`, or the environment variable
//!   `EDMD_DIR`; nothing of it is in this repository: it is Frank Smallenburg's EDMD, MIT
//!   licence, published with Eur. Phys. J. E 45, 22 (2022), arXiv 2201.01100, whose folder
//!   holds `mdSingle.c`) with `cc -O3 -march=native`, its settings edited in a copy:
//!   an FCC start at the packing fraction, `N` spheres (four times a cube), no thermostat, a
//!   run long enough for about `C` collisions (default 3e6) by Enskog's rate, rounded up to
//!   a whole time unit (it prints its collision count once per time unit). Without it, the
//!   bench says so and runs ours alone for `C` collisions.
//! - Ours: the same `N`, packing and number of collisions as EDMD's run: `kinetic-collide
//!   generate --periodic`'s system (a lattice start above packing 0.3, random below),
//!   simulated on [`ListedSpheres`] in a fresh process with no event log written; with
//!   `--tool PATH` (the built `kinetic-collide`), the tool itself: `generate --periodic`
//!   writes the system (not timed), and `run --events none --stats` is the process timed.
//! - `--walls` (with `--tool`): the same spheres inside walls too (`generate` without
//!   `--periodic`, the same number of collisions), interleaved with the periodic runs, and
//!   the ratio of their collision rates (the walls' median over the periodic box's).
//!
//! Both are timed as whole processes (start, simulation, exit) and their peak resident memory
//! is the process's (GNU time's maximum resident set). The table goes to standard output and
//! the CSV to `--out` (default `docs/results/edmd.csv`).

use kinetic_collide::scene::outer_radius;
use kinetic_collide::spheres::ListedSpheres;
use kinetic_collide_cli::process::{peak_kb, run_child, timed};
use kinetic_scenes::hard_spheres::HardSpheres;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A system: number of spheres and packing fraction.
#[derive(Clone, Copy, Debug)]
struct System {
    n: usize,
    packing: f64,
}

impl System {
    fn parse(text: &str) -> Result<System, String> {
        let (n, p) = text
            .split_once(':')
            .ok_or_else(|| format!("{text:?}: expected N:PACKING"))?;
        Ok(System {
            n: n.parse().map_err(|e| format!("{text:?}: {e}"))?,
            packing: p.parse().map_err(|e| format!("{text:?}: {e}"))?,
        })
    }

    fn name(&self) -> String {
        format!("{}:{}", self.n, self.packing)
    }

    fn spheres(&self, collisions: f64) -> HardSpheres {
        HardSpheres {
            n: self.n,
            packing: self.packing,
            collisions,
            periodic: true,
            ..HardSpheres::gas(self.n)
        }
    }
}

/// One side's run.
#[derive(Clone, Copy, Debug)]
struct Measured {
    collisions: f64,
    seconds: f64,
    peak_kb: f64,
    /// `PV / NkT` over the run.
    z: f64,
}

impl Measured {
    fn rate(&self) -> f64 {
        self.collisions / self.seconds
    }
}

/// The run of median rate.
fn median(mut runs: Vec<Measured>) -> Option<Measured> {
    runs.sort_by(|a, b| a.rate().total_cmp(&b.rate()));
    runs.get(runs.len() / 2).copied()
}

/// The child: simulates `collisions` collisions of the system and prints
/// `collisions seconds peak_kb z`, the seconds from the process's start.
fn child(system: System, collisions: f64) -> Result<(), String> {
    let start = Instant::now();
    let scene = system
        .spheres(collisions)
        .build()
        .map_err(|e| e.to_string())?;
    let cell = scene.periodic.ok_or("no periodic box")?;
    let spheres: Vec<_> = scene
        .objects
        .iter()
        .map(|o| (outer_radius(&o.shape), o.plan()))
        .collect();
    drop(scene);
    let mut gas = ListedSpheres::periodic(cell, &spheres).map_err(|e| e.to_string())?;
    drop(spheres);
    // Enskog's rate sets the pace; the run goes on until the count is reached.
    let per_unit = system.spheres(collisions).collision_rate();
    let mut done = 0.0;
    while done < collisions {
        let ahead = ((collisions - done) / per_unit).max(1e-3);
        gas.advance_to(gas.now() + ahead.min(0.02))
            .map_err(|e| e.to_string())?;
        gas.drain_events();
        done = gas
            .stats()
            .events_by_kind
            .get("collision")
            .copied()
            .unwrap_or(0) as f64;
    }
    let z = gas.bulk().compressibility;
    println!("{done} {} {} {z}", start.elapsed().as_secs_f64(), peak_kb());
    Ok(())
}

fn ours(system: System, collisions: f64) -> Result<Measured, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let run = timed(
        Path::new("."),
        &exe,
        &["--child", &system.name(), &collisions.to_string()],
    )?;
    let v: Vec<f64> = run
        .stdout
        .split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect();
    match v.as_slice() {
        [c, _, _, z] => Ok(Measured {
            collisions: *c,
            seconds: run.seconds,
            peak_kb: run.peak_kb,
            z: *z,
        }),
        _ => Err(format!("child printed {:?}", run.stdout)),
    }
}

/// EDMD built for one system in a scratch folder.
/// Ours from the command-line tool: `generate --periodic` (or, not `periodic`, `generate`:
/// inside walls) writes the system (not timed), then `run --events none --stats` is the
/// timed process; the collisions and `Z` are read from its statistics.
fn ours_tool(
    tool: &Path,
    system: System,
    collisions: f64,
    periodic: bool,
) -> Result<Measured, String> {
    let work = std::env::temp_dir().join(format!("kinetic-collide-tool-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let scene = work.join(format!("{}-{periodic}.json", system.name()));
    let stats = work.join("stats.json");
    let generated = std::process::Command::new(tool)
        .arg("generate")
        .args(periodic.then_some("--periodic"))
        .args(["--n", &system.n.to_string()])
        .args(["--packing", &system.packing.to_string()])
        .args(["--collisions", &collisions.to_string(), "-o"])
        .arg(&scene)
        .output()
        .map_err(|e| format!("{}: {e}", tool.display()))?;
    if !generated.status.success() {
        return Err(String::from_utf8_lossy(&generated.stderr).into_owned());
    }
    let (scene, stats_path) = (scene.to_string_lossy(), stats.to_string_lossy());
    let run = timed(
        &work,
        tool,
        &["run", &scene, "--events", "none", "--stats", &stats_path],
    )?;
    let text = std::fs::read_to_string(&stats).map_err(|e| e.to_string())?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let collisions = v["events"]["by_kind"]["collision"]
        .as_f64()
        .ok_or("no collision count in the statistics")?;
    let z = v["bulk"]["compressibility"].as_f64().unwrap_or(f64::NAN);
    Ok(Measured {
        collisions,
        seconds: run.seconds,
        peak_kb: run.peak_kb,
        z,
    })
}

struct Edmd {
    work: PathBuf,
}

impl Edmd {
    /// Copies the sources, edits the settings and builds.
    fn build(source: &Path, system: System, time: f64) -> Result<Edmd, String> {
        let k = (system.n as f64 / 4.0).cbrt().round() as usize;
        if 4 * k * k * k != system.n {
            return Err(format!(
                "EDMD's FCC start needs N = 4 k^3, not {}",
                system.n
            ));
        }
        let work = std::env::temp_dir().join(format!(
            "kinetic-collide-edmd-{}-{}",
            std::process::id(),
            system.name()
        ));
        std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
        for file in ["mdSingle.h", "mt19937ar.c"] {
            std::fs::copy(source.join(file), work.join(file))
                .map_err(|e| format!("{}: {e}", source.join(file).display()))?;
        }
        let mut text = std::fs::read_to_string(source.join("mdSingle.c"))
            .map_err(|e| format!("{}: {e}", source.join("mdSingle.c").display()))?;
        let settings = [
            ("double maxtime = ", format!("{time:.1}")),
            ("int initialconfig = ", "1".to_string()),
            ("double packfrac = ", format!("{}", system.packing)),
            ("int N = ", format!("{}", system.n)),
            ("const int usethermostat = ", "0".to_string()),
        ];
        for (prefix, value) in settings {
            let at = text
                .find(prefix)
                .ok_or_else(|| format!("mdSingle.c: no `{prefix}` setting"))?;
            let end = at
                + text[at..]
                    .find(';')
                    .ok_or("mdSingle.c: unterminated setting")?;
            text.replace_range(at + prefix.len()..end, &value);
        }
        std::fs::write(work.join("mdSingle.c"), text).map_err(|e| e.to_string())?;
        let out = std::process::Command::new("cc")
            .current_dir(&work)
            .args(["-O3", "-march=native", "mdSingle.c", "-o", "md", "-lm"])
            .output()
            .map_err(|e| format!("cc: {e}"))?;
        if !out.status.success() {
            return Err(format!("cc: {}", String::from_utf8_lossy(&out.stderr)));
        }
        Ok(Edmd { work })
    }

    /// One run: the collisions at the last whole time unit, and the whole process.
    fn measure(&self) -> Result<Measured, String> {
        let run = timed(&self.work, &self.work.join("md"), &[])?;
        let last = run
            .stdout
            .lines()
            .rev()
            .find(|l| l.starts_with("Simtime:"))
            .ok_or("EDMD printed no Simtime line")?;
        let number_after = |key: &str| -> Option<f64> {
            last.split(key)
                .nth(1)?
                .split(|c: char| c == ',' || c.is_whitespace())
                .find(|w| !w.is_empty())?
                .parse()
                .ok()
        };
        let collisions = number_after("Collisions:").ok_or("no collision count")?;
        let pressure = number_after("Press:").ok_or("no pressure")?;
        let temperature = number_after("T:").unwrap_or(1.0);
        let n = self.n()?;
        let volume = n * std::f64::consts::PI / 6.0 / self.packing()?;
        Ok(Measured {
            collisions,
            seconds: run.seconds,
            peak_kb: run.peak_kb,
            z: pressure * volume / (n * temperature),
        })
    }

    fn setting(&self, prefix: &str) -> Result<f64, String> {
        let text =
            std::fs::read_to_string(self.work.join("mdSingle.c")).map_err(|e| e.to_string())?;
        let at = text.find(prefix).ok_or("setting")? + prefix.len();
        text[at..at + text[at..].find(';').ok_or("setting")?]
            .trim()
            .parse()
            .map_err(|e| format!("{e}"))
    }

    fn n(&self) -> Result<f64, String> {
        self.setting("int N = ")
    }

    fn packing(&self) -> Result<f64, String> {
        self.setting("double packfrac = ")
    }
}

impl Drop for Edmd {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.work);
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if run_child(&args, System::parse, child) {
        return;
    }
    let mut source = std::env::var_os("EDMD_DIR").map(PathBuf::from);
    let mut collisions = 3e6;
    let mut repeat = 3usize;
    let mut out = PathBuf::from("docs/results/edmd.csv");
    let mut tool: Option<PathBuf> = None;
    let mut walls = false;
    let mut systems = vec![
        System {
            n: 32000,
            packing: 0.26,
        },
        System {
            n: 32000,
            packing: 0.45,
        },
    ];
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().cloned().unwrap_or_default();
        match a.as_str() {
            "--edmd" => source = Some(PathBuf::from(value())),
            "--collisions" => collisions = value().parse().expect("--collisions: a number"),
            "--repeat" => repeat = value().parse::<usize>().expect("--repeat: a count").max(1),
            "--out" => out = PathBuf::from(value()),
            "--tool" => {
                let path = PathBuf::from(value());
                // The runs start in a folder of their own.
                tool = Some(std::fs::canonicalize(&path).unwrap_or(path));
            }
            "--systems" => {
                systems = value()
                    .split(',')
                    .map(|s| System::parse(s).unwrap_or_else(|e| panic!("--systems: {e}")))
                    .collect()
            }
            "--walls" => walls = true,
            "--bench" => {}
            other => panic!("unknown argument {other}"),
        }
    }
    let source = match source {
        Some(dir) if dir.join("mdSingle.c").exists() => Some(dir),
        Some(dir) => {
            eprintln!(
                "EDMD's sources are not in {}: running kinetic-collide alone",
                dir.display()
            );
            None
        }
        None => {
            eprintln!(
                "no EDMD folder given (--edmd DIR or EDMD_DIR): running kinetic-collide alone"
            );
            None
        }
    };
    if walls && tool.is_none() {
        panic!("--walls: runs the tool, named with --tool PATH");
    }
    let mut walls_table = String::from(
        "| spheres | packing | periodic collisions/s | in walls collisions/s | walls / periodic |\n\
         |---|---|---|---|---|\n",
    );
    let mut csv = String::from(
        "n,packing,collisions,ours_seconds,ours_rate,ours_peak_mb,ours_z,\
         edmd_seconds,edmd_rate,edmd_peak_mb,edmd_z,rate_ratio,memory_ratio,carnahan_starling_z\n",
    );
    let mut table = String::from(
        "| spheres | packing | collisions | kinetic-collide collisions/s | peak memory | \
         EDMD collisions/s | peak memory | rate ratio | memory ratio | Z ours / EDMD / CS |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for system in systems {
        let name = system.name();
        let spheres = system.spheres(collisions);
        // EDMD prints its count once per time unit: a whole number of units.
        let time = (collisions / spheres.collision_rate()).ceil().max(1.0);
        let edmd = if let Some(source) = &source {
            match Edmd::build(source, system, time) {
                Ok(e) => Some(e),
                Err(e) => {
                    eprintln!("{name}: EDMD: {e}");
                    None
                }
            }
        } else {
            None
        };
        let (mut ours_runs, mut edmd_runs, mut walls_runs) = (Vec::new(), Vec::new(), Vec::new());
        for r in 1..=repeat {
            let mut target = collisions;
            if let Some(e) = &edmd {
                eprintln!("{name}: EDMD, run {r} of {repeat} ...");
                match e.measure() {
                    Ok(m) => {
                        target = m.collisions;
                        edmd_runs.push(m);
                    }
                    Err(e) => eprintln!("{name}: EDMD: {e}"),
                }
            }
            eprintln!("{name}: kinetic-collide, run {r} of {repeat} ...");
            let measured = match &tool {
                Some(tool) => ours_tool(tool, system, target, true),
                None => ours(system, target),
            };
            match measured {
                Ok(m) => ours_runs.push(m),
                Err(e) => eprintln!("{name}: kinetic-collide: {e}"),
            }
            if let Some(tool) = tool.as_ref().filter(|_| walls) {
                eprintln!("{name}: kinetic-collide in walls, run {r} of {repeat} ...");
                match ours_tool(tool, system, target, false) {
                    Ok(m) => walls_runs.push(m),
                    Err(e) => eprintln!("{name}: kinetic-collide in walls: {e}"),
                }
            }
        }
        let eta = system.packing;
        let cs = (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3);
        let Some(k) = median(ours_runs) else {
            continue;
        };
        if let Some(w) = median(walls_runs) {
            let _ = writeln!(
                walls_table,
                "| {} | {} | {:.0} | {:.0} | {:.2}x |",
                system.n,
                system.packing,
                k.rate(),
                w.rate(),
                w.rate() / k.rate()
            );
        }
        let d = median(edmd_runs);
        let mb = |kb: f64| kb / 1024.0;
        let _ = write!(
            table,
            "| {} | {} | {:.3e} | {:.0} | {:.1} MB |",
            system.n,
            system.packing,
            k.collisions,
            k.rate(),
            mb(k.peak_kb)
        );
        let _ = write!(
            csv,
            "{},{},{},{:.3},{:.0},{:.1},{:.4},",
            system.n,
            system.packing,
            k.collisions,
            k.seconds,
            k.rate(),
            mb(k.peak_kb),
            k.z
        );
        match d {
            Some(d) => {
                let _ = writeln!(
                    table,
                    " {:.0} | {:.1} MB | {:.2}x | {:.2}x | {:.3} / {:.3} / {cs:.3} |",
                    d.rate(),
                    mb(d.peak_kb),
                    k.rate() / d.rate(),
                    k.peak_kb / d.peak_kb,
                    k.z,
                    d.z
                );
                let _ = writeln!(
                    csv,
                    "{:.3},{:.0},{:.1},{:.4},{:.3},{:.3},{cs:.4}",
                    d.seconds,
                    d.rate(),
                    mb(d.peak_kb),
                    d.z,
                    k.rate() / d.rate(),
                    k.peak_kb / d.peak_kb
                );
            }
            None => {
                let _ = writeln!(table, " - | - | - | - | {:.3} / - / {cs:.3} |", k.z);
                let _ = writeln!(csv, ",,,,,,{cs:.4}");
            }
        }
    }
    print!("{table}");
    if walls {
        print!("\n{walls_table}");
    }
    if let Err(e) = std::fs::write(&out, &csv) {
        eprintln!("{}: {e}", out.display());
    } else {
        eprintln!("wrote {}", out.display());
    }
}
