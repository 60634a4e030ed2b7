//! Hard-sphere systems, kinetic-collide against DynamO, side by side in one run.
//!
//! ```text
//! cargo bench --bench dynamo -- [--dynamo DIR] [--collisions C] [--systems LIST] [--repeat K]
//!                                [--dynamo-budget S] [--out FILE]
//! ```
//!
//! For each system (`gas:N` or `mix:RATIO:N`, default: the gas at 4000, 32000 and 256000, the
//! mixtures 0.5, 0.2 and 0.1 at 32000) it generates the scene (`kinetic-collide generate`'s
//! generator, seed 1), runs it on the structure the tool picks (the neighbour lists for the
//! gas, the cell grid for the mixtures) in a fresh process (the tool's `run`
//! minus file output: the event log is formatted as it goes and dropped), and reports
//! collisions per second, the process's peak memory per sphere, and the wall time for `C`
//! collisions (default 1e6). Each side runs K times (default 3), interleaved, and the row
//! shows each side's median run: timings on a shared machine vary by 10-30% from run to run.
//!
//! DynamO: pass `--dynamo DIR` with `DIR/dynarun` built from its public source (nothing of it
//! is in this repository). It runs the same spheres from the same start (positions and
//! velocities written as a DynamO configuration, in its periodic box of the same side) for the
//! same number of collisions, or fewer where that would take more than `--dynamo-budget`
//! seconds (default 120), the time for 1e6 then scaled from its rate. Without DynamO the table
//! holds our figures only.

use kinetic_collide::Structure;
use kinetic_collide::run::push_event_line;
use kinetic_collide::scene::outer_radius;
use kinetic_collide::spheres::{ElasticCells, ListedSpheres};
use kinetic_collide::{ContactKind, Walls};
use kinetic_collide_cli::process::{peak_kb, run_child};
use kinetic_scenes::hard_spheres::HardSpheres;
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

/// The hard-sphere simulator a system runs on.
enum Sim {
    Cells(ElasticCells),
    Lists(ListedSpheres),
}

/// The child: runs one system and prints `collisions seconds peak_kb`.
fn child(system: System, collisions: f64) -> Result<(), String> {
    let scene = system
        .spheres(collisions)
        .build()
        .map_err(|e| e.to_string())?;
    let structure = Structure::for_scene(&scene);
    if !matches!(structure, Structure::Cells | Structure::Lists) {
        return Err(format!("{}: not a hard-sphere system", system.name()));
    }
    let balls: Vec<_> = scene
        .objects
        .iter()
        .map(|o| (outer_radius(&o.shape), o.plan()))
        .collect();
    let walls: Walls = scene.walls.ok_or("no walls")?;
    let start = Instant::now();
    let mut sim = if structure == Structure::Cells {
        Sim::Cells(ElasticCells::new(walls, &balls).map_err(|e| e.to_string())?)
    } else {
        Sim::Lists(ListedSpheres::in_walls(walls, &balls).map_err(|e| e.to_string())?)
    };
    let mut log = String::new();
    let mut sink = std::io::sink();
    let chunks = 100;
    let mut begun = 0u64;
    for k in 1..=chunks {
        let to = scene.horizon * k as f64 / chunks as f64;
        let events = match &mut sim {
            Sim::Cells(cells) => cells.advance_to(to).map(|()| cells.drain_events()),
            Sim::Lists(lists) => lists.advance_to(to).map(|()| lists.drain_events()),
        }
        .map_err(|e| e.to_string())?;
        log.clear();
        for e in events {
            begun += u64::from(e.kind == ContactKind::Begin);
            push_event_line(&mut log, &e);
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

/// Runs `cmd` (under GNU time printing `PEAK_KB=`): its peak KiB, or why it failed.
fn peak_kb_of(cmd: &mut Command) -> Result<f64, String> {
    let out = cmd.output().map_err(|e| e.to_string())?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!("{cmd:?} failed: {stderr}"));
    }
    Ok(stderr
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("PEAK_KB="))
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN))
}

/// The system as a DynamO configuration: the same spheres, positions and velocities, in
/// DynamO's periodic box of the same side (centred on the origin), its neighbour-list
/// scheduler and hard-sphere interactions per species pair.
fn dynamo_config(scene: &kinetic_collide::scene::Scene, h: &HardSpheres) -> String {
    let side = h.side();
    let species = h.species();
    let mut x = String::new();
    let _ = write!(
        x,
        "<?xml version=\"1.0\"?>\n<DynamOconfig version=\"1.5.0\">\n  <Simulation>\n    \
         <Scheduler Type=\"NeighbourList\">\n      <Sorter Type=\"BoundedPQMinMax3\"/>\n    \
         </Scheduler>\n    <SimulationSize x=\"{side:.17}\" y=\"{side:.17}\" z=\"{side:.17}\"/>\n    <Genus>\n"
    );
    let mut first = 0;
    let ranges: Vec<(usize, usize)> = species
        .iter()
        .map(|s| {
            let r = (first, first + s.count - 1);
            first += s.count;
            r
        })
        .collect();
    for (k, (s, (lo, hi))) in species.iter().zip(&ranges).enumerate() {
        let _ = write!(
            x,
            "      <Species Mass=\"{:.17}\" Name=\"S{k}\" Type=\"Point\">\n        \
             <IDRange Type=\"Ranged\" Start=\"{lo}\" End=\"{hi}\"/>\n      </Species>\n",
            s.mass
        );
    }
    x.push_str("    </Genus>\n    <BC Type=\"PBC\"/>\n    <Topology/>\n    <Interactions>\n");
    let range = |(lo, hi): (usize, usize)| {
        format!("<IDRange Type=\"Ranged\" Start=\"{lo}\" End=\"{hi}\"/>")
    };
    for i in 0..species.len() {
        for j in i..species.len() {
            let d = (species[i].diameter + species[j].diameter) / 2.0;
            let pairs = if i == j {
                format!(
                    "<IDPairRange Type=\"Single\">{}</IDPairRange>",
                    range(ranges[i])
                )
            } else {
                format!(
                    "<IDPairRange Type=\"Pair\">{}{}</IDPairRange>",
                    range(ranges[i]),
                    range(ranges[j])
                )
            };
            let _ = writeln!(
                x,
                "      <Interaction Type=\"HardSphere\" Diameter=\"{d:.17}\" Name=\"I{i}{j}\">{pairs}</Interaction>"
            );
        }
    }
    x.push_str(
        "    </Interactions>\n    <Locals/>\n    <Globals/>\n    <SystemEvents/>\n    \
         <Dynamics Type=\"Newtonian\"/>\n  </Simulation>\n  <Properties/>\n  <ParticleData>\n",
    );
    for (id, o) in scene.objects.iter().enumerate() {
        let p = o.position - glam::DVec3::splat(side / 2.0);
        let v = o.velocity;
        let _ = writeln!(
            x,
            "    <Pt ID=\"{id}\"><P x=\"{:.17}\" y=\"{:.17}\" z=\"{:.17}\"/><V x=\"{:.17}\" y=\"{:.17}\" z=\"{:.17}\"/></Pt>",
            p.x, p.y, p.z, v.x, v.y, v.z
        );
    }
    x.push_str("  </ParticleData>\n</DynamOconfig>\n");
    x
}

/// DynamO on one system: its configuration written to a work folder, and the number of
/// collisions each measured run makes.
struct DynamoRun<'a> {
    dir: &'a Path,
    work: PathBuf,
    config: PathBuf,
    count: f64,
}

impl<'a> DynamoRun<'a> {
    /// The same system from the same start; a probe of 2e4 collisions sizes each measured
    /// run to the budget.
    fn new(dir: &'a Path, system: System, collisions: f64, budget: f64) -> Result<Self, String> {
        let work = std::env::temp_dir().join(format!("kinetic-dynamo-{}", std::process::id()));
        std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
        let h = system.spheres(collisions);
        let scene = h.build().map_err(|e| e.to_string())?;
        let config = work.join("config.xml");
        std::fs::write(&config, dynamo_config(&scene, &h)).map_err(|e| e.to_string())?;
        let probe = 2e4f64.min(collisions);
        let (rate, _) = dynarun(dir, &work, &config, probe)?;
        let count = collisions.min((budget * rate).max(probe)).round();
        Ok(DynamoRun {
            dir,
            work,
            config,
            count,
        })
    }

    /// One measured run: collisions per second are DynamO's own `EventsPerSec` (its run
    /// time without reading the configuration), memory is the process's peak.
    fn measure(&self) -> Result<Measured, String> {
        let (rate, peak_kb) = dynarun(self.dir, &self.work, &self.config, self.count)?;
        Ok(Measured {
            collisions: self.count,
            seconds: self.count / rate,
            peak_kb,
        })
    }
}

impl Drop for DynamoRun<'_> {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.work);
    }
}

/// The run of median rate.
fn median(mut runs: Vec<Measured>) -> Option<Measured> {
    runs.sort_by(|a, b| a.rate().total_cmp(&b.rate()));
    runs.get(runs.len() / 2).copied()
}

/// One `dynarun` for `count` collisions: its collisions per second and peak KiB.
fn dynarun(dir: &Path, work: &Path, config: &Path, count: f64) -> Result<(f64, f64), String> {
    let output = work.join("output.xml");
    let mut cmd = Command::new("/usr/bin/time");
    cmd.current_dir(work)
        .args(["-f", "PEAK_KB=%M"])
        .arg(dir.join("dynarun"))
        .arg(config)
        .args(["-c", &format!("{count}"), "-o"])
        .arg(work.join("config.end.xml"))
        .arg("--out-data-file")
        .arg(&output);
    let peak = peak_kb_of(&mut cmd)?;
    let text =
        std::fs::read_to_string(&output).map_err(|e| format!("{}: {e}", output.display()))?;
    let rate = text
        .split("EventsPerSec=\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .and_then(|r| r.parse::<f64>().ok())
        .ok_or("no EventsPerSec in DynamO's output")?;
    Ok((rate, peak))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if run_child(&args, System::parse, child) {
        return;
    }
    let mut dynamo_dir: Option<PathBuf> = None;
    let mut collisions = 1e6;
    let mut budget = 120.0;
    let mut repeat = 3usize;
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
            "--dynamo" => {
                let dir = PathBuf::from(value());
                dynamo_dir = Some(std::fs::canonicalize(&dir).unwrap_or(dir));
            }
            "--collisions" => collisions = value().parse().expect("--collisions: a number"),
            "--dynamo-budget" => budget = value().parse().expect("--dynamo-budget: seconds"),
            "--out" => out = PathBuf::from(value()),
            "--repeat" => repeat = value().parse::<usize>().expect("--repeat: a count").max(1),
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
        // Each side runs `repeat` times, the two interleaved so that both meet the same
        // load on the machine; the row shows each side's median run.
        let dynamo = match dynamo_dir.as_deref() {
            Some(d) => {
                eprintln!("{name}: DynamO probe ...");
                DynamoRun::new(d, system, collisions, budget).map(Some)
            }
            None => Ok(None),
        };
        let (mut ours_runs, mut dynamo_runs) = (Vec::new(), Vec::new());
        let mut failed = None;
        for r in 1..=repeat {
            eprintln!("{name}: kinetic-collide, run {r} of {repeat} ...");
            match ours(system, collisions) {
                Ok(k) => ours_runs.push(k),
                Err(e) => {
                    failed = Some(e);
                    break;
                }
            }
            if let Ok(Some(d)) = &dynamo {
                eprintln!("{name}: DynamO, run {r} of {repeat} ...");
                match d.measure() {
                    Ok(m) => dynamo_runs.push(m),
                    Err(e) => eprintln!("{name}: DynamO: {e}"),
                }
            }
        }
        let Some(k) = median(ours_runs) else {
            eprintln!("{name}: {}", failed.unwrap_or_default());
            continue;
        };
        let n = system.n as f64;
        let mut row = format!(
            "| {name} | {} | {:.0} | {:.0} B | {:.2} s |",
            system.n,
            k.rate(),
            k.peak_kb * 1024.0 / n,
            1e6 / k.rate()
        );
        match (dynamo, median(dynamo_runs)) {
            (Ok(Some(_)), Some(d)) => {
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
            (Err(e), _) => {
                eprintln!("{name}: DynamO: {e}");
                row.push_str(" - | - | - | - |");
            }
            _ => row.push_str(" - | - | - | - |"),
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
