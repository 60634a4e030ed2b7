//! The `kinetic-collide` command-line tool: runs a scene file and writes its exact event log.

use clap::builder::PossibleValuesParser;
use clap::{Parser, Subcommand};
use kinetic_collide::ContactEvent;
use kinetic_collide::Structure;
use kinetic_collide::run::{RunError, Stream, push_event_line, run_periodic_streamed};
use kinetic_collide::scene::Scene;
use kinetic_collide_cli::frames::{
    FrameSpec, Overlay, render_series, run_with_snapshots, run_with_snapshots_streamed, write_run,
};
use kinetic_collide_cli::input::{InputError, read_scene_text};
use kinetic_collide_cli::output::{self, Output, Target, write_whole};
use kinetic_collide_cli::progress::Progress;
use kinetic_render::Snapshot;
use kinetic_scenes::BallScene;
use kinetic_scenes::hard_spheres::HardSpheres;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exact kinetic collision detection for moving objects.
///
/// With no command, runs the built-in scene (marbles on a table) and writes its scene, event
/// log, statistics and 60 PNG frames under out/marbles_on_a_table/.
#[derive(Parser, Debug)]
#[command(name = "kinetic-collide", version)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scene file and write its event log (JSON Lines) and statistics.
    Run {
        /// The scene file (JSON, see the scene format).
        scene: PathBuf,
        /// Where to write the event log (default: standard output); `none` writes no log
        /// (the statistics still), so a long run costs only its simulation (a file of that
        /// name is `./none`).
        #[arg(long)]
        events: Option<PathBuf>,
        /// Where to write the statistics (JSON).
        #[arg(long)]
        stats: Option<PathBuf>,
        /// The kinetic structure (default: the fastest for the scene, chosen from it).
        #[arg(long, value_name = "NAME", value_parser = PossibleValuesParser::new(Structure::ALL.map(Structure::name)))]
        structure: Option<String>,
        /// In a periodic box, measure the bulk figures (collision rate, pressure) from this
        /// simulated time to the horizon, leaving out the start (melting from a lattice, say);
        /// default 0, the whole run.
        #[arg(long, value_name = "TIME")]
        measure_from: Option<f64>,
        /// Also render N frames at even times over the horizon, as PNG.
        #[arg(long, value_name = "N", default_value_t = 0)]
        frames: usize,
        /// Where the frames go (default: out/<scene file name>/).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Frame size, WxH.
        #[arg(long, value_name = "WxH", default_value = "640x480")]
        size: String,
        /// What to draw over the objects: none, candidates (candidate-pair lines) or boxes
        /// (the structure's boxes: threshold boxes, sweep or guard boxes).
        #[arg(long, value_name = "NAME", default_value = "none")]
        overlay: String,
    },
    /// Run scenes with every applicable method (kinetic structures, time-stepped detection,
    /// rapier and avian with and without CCD and with the kinetic broad phase) and score each against
    /// the exact log: wall time, contacts missed, contact-time error, false contacts. Prints a
    /// Markdown table and writes compare.csv and compare.png.
    Compare {
        /// Scene files, built-in families (marbles, gas, asteroids, bullets, pile; NAME or
        /// NAME:OBJECTS) or stability cases (lattice, grazes, start-in-contact, offset-1e6,
        /// offset-1e9, radii-1e-6-1e6, speed-1e6, zeno). Default: every family.
        scenes: Vec<String>,
        /// Where the CSV and the chart go.
        #[arg(long, value_name = "DIR", default_value = "out/compare")]
        out: PathBuf,
    },
    /// Write a hard-sphere scene (the benchmark systems of DynamO and EDMD): a gas of equal
    /// spheres or a binary mixture with equal volume fractions, inside walls or in a periodic
    /// box, elastic, Maxwell-Boltzmann velocities at kT = 1, large spheres of diameter and
    /// mass 1.
    Generate {
        /// Number of spheres (at most 100,000,000).
        #[arg(long, default_value_t = 4000)]
        n: usize,
        /// Small over large diameter, in (0, 1]; 1 gives the monodisperse gas.
        #[arg(long, default_value_t = 1.0)]
        ratio: f64,
        /// Fraction of the box the spheres fill (at most 0.55; above 0.3 the spheres start on
        /// a face-centred cubic lattice, which the run melts).
        #[arg(long, default_value_t = 0.26)]
        packing: f64,
        /// Horizon: about this many collisions (Enskog's rate).
        #[arg(long, default_value_t = 1e6)]
        collisions: f64,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// A periodic box instead of walls (bulk figures: collision rate and pressure).
        #[arg(long)]
        periodic: bool,
        /// Where to write the scene (default: standard output).
        #[arg(long, short)]
        out: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let result = match cli.command {
        None => default_scene(),
        Some(Command::Compare { scenes, out }) => compare(&scenes, &out),
        Some(Command::Generate {
            n,
            ratio,
            packing,
            collisions,
            seed,
            periodic,
            out,
        }) => generate(
            HardSpheres {
                n,
                ratio,
                packing,
                collisions,
                seed,
                periodic,
            },
            out.as_deref(),
        ),
        Some(Command::Run {
            scene,
            events,
            stats,
            structure,
            measure_from,
            frames,
            out,
            size,
            overlay,
        }) => frame_request(&scene, frames, out, &size, &overlay).and_then(|frames| {
            run_file(
                &scene,
                Outputs {
                    events: events.as_deref(),
                    stats: stats.as_deref(),
                    frames,
                },
                structure.as_deref(),
                measure_from,
            )
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err((code, message)) => {
            eprintln!("kinetic-collide: {message}");
            ExitCode::from(code)
        }
    }
}

type Failure = (u8, String);

/// Writes `text` to standard output; a reader that went away is no failure.
fn to_stdout(text: &str) -> Result<(), Failure> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if output::is_broken_pipe(&e) => Ok(()),
        Err(e) => Err((1, format!("standard output: cannot write: {e}"))),
    }
}

/// Frames asked for: the spec and the folder.
type Frames = Option<(FrameSpec, PathBuf)>;

fn frame_request(
    scene: &Path,
    count: usize,
    out: Option<PathBuf>,
    size: &str,
    overlay: &str,
) -> Result<Frames, Failure> {
    let (width, height) = FrameSpec::parse_size(size).map_err(|e| (2, e.to_string()))?;
    let overlay = Overlay::parse(overlay).map_err(|e| (2, e.to_string()))?;
    if count == 0 {
        return Ok(None);
    }
    let name = scene
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let dir = out.unwrap_or_else(|| Path::new("out").join(name));
    let spec = FrameSpec {
        count,
        width,
        height,
        overlay,
    };
    Ok(Some((spec, dir)))
}

/// Set by SIGINT and SIGTERM: the run stops at the next instant and writes what it has.
static STOP: AtomicBool = AtomicBool::new(false);

/// What a run writes: the log, the statistics and the frames.
struct Outputs<'a> {
    events: Option<&'a Path>,
    stats: Option<&'a Path>,
    frames: Frames,
}

fn run_file(
    path: &Path,
    outputs: Outputs<'_>,
    structure: Option<&str>,
    measure_from: Option<f64>,
) -> Result<(), Failure> {
    let Outputs {
        events,
        stats,
        frames,
    } = outputs;
    let structure = structure
        .map(|name| {
            Structure::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = Structure::ALL.map(Structure::name).to_vec();
                (
                    2,
                    format!(
                        "--structure: unknown structure {name:?} (expected one of: {})",
                        names.join(", ")
                    ),
                )
            })
        })
        .transpose()?;
    let from_stdin = output::is_dash(path);
    let shown = if from_stdin {
        "standard input".to_string()
    } else {
        path.display().to_string()
    };
    let dash = Path::new("-");
    let no_log = events.is_some_and(|p| p.as_os_str() == "none");
    let mut named = Vec::new();
    if !no_log {
        named.push(("--events", events.unwrap_or(dash)));
    }
    if let Some(p) = stats {
        named.push(("--stats", p));
    }
    let input = (!from_stdin).then_some(path);
    let targets = output::plan_outputs(input, &named).map_err(|e| (2, e))?;
    let (log_target, stats_target) = if no_log {
        (None, targets.first())
    } else {
        (targets.first(), targets.get(1))
    };
    let read = if from_stdin {
        read_scene_text(std::io::stdin().lock())
    } else {
        std::fs::File::open(path)
            .map_err(InputError::Read)
            .and_then(read_scene_text)
    };
    let text = read.map_err(|e| (2, format!("{shown}: {e}")))?;
    let scene = Scene::from_json(&text).map_err(|e| (2, format!("{shown}: {e}")))?;
    drop(text);
    let spec = frames
        .as_ref()
        .map_or(FrameSpec::default(), |(spec, _)| *spec);
    let cannot_write = |target: &Target, e: std::io::Error| {
        let name = match target {
            Target::Stdout => "standard output".to_string(),
            Target::File(p) | Target::Special(p) => p.display().to_string(),
        };
        (1, format!("{name}: cannot write: {e}"))
    };
    let mut log = match log_target {
        Some(target) => Some(Output::open(target).map_err(|e| cannot_write(target, e))?),
        None => None,
    };
    // The first signal stops the run at the next instant; a second (say, during a long build
    // that has no instants yet) exits at once, leaving no partial file.
    let _ = ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::Relaxed) {
            output::remove_hidden_files();
            std::process::exit(130);
        }
    });
    let mut progress = Progress::new(scene.horizon);
    let mut write_error: Option<std::io::Error> = None;
    let mut line = String::with_capacity(1 << 16);
    let mut sink = |batch: &[ContactEvent]| {
        if let Some(last) = batch.last() {
            progress.reached(last.time, batch.len());
        }
        let Some(log) = log.as_mut() else {
            return ControlFlow::Continue(());
        };
        line.clear();
        for e in batch {
            push_event_line(&mut line, e);
        }
        match log.write_all(line.as_bytes()) {
            Ok(()) => ControlFlow::Continue(()),
            Err(e) => {
                let reason = format!("the event log could not be written: {e}");
                write_error = Some(e);
                ControlFlow::Break(reason)
            }
        }
    };
    let mut stream = Stream {
        sink: &mut sink,
        stop: Some(&STOP),
    };
    let result = match measure_from {
        Some(from) if structure.is_none_or(|s| s == Structure::Periodic) && frames.is_none() => {
            run_periodic_streamed(&scene, from, &mut stream).map(|out| (out, Vec::new()))
        }
        Some(_) => Err(RunError::Input(
            "--measure-from: applies to the periodic structure, without frames".to_string(),
        )),
        None => run_with_snapshots_streamed(&scene, structure, &spec, &mut stream),
    };
    progress.finish();
    let (output, snapshots, stopped) = match result {
        Ok((out, snapshots)) => (out, snapshots, None),
        Err(RunError::Input(msg)) => return Err((2, format!("{shown}: {msg}"))),
        Err(RunError::Stopped {
            time,
            source,
            partial,
        }) => (
            *partial,
            Vec::new(),
            Some(format!("run stopped at t = {time}: {source}")),
        ),
    };
    let written = match (write_error, log) {
        (Some(e), log) => {
            drop(log);
            Err(e)
        }
        (None, Some(log)) => log.commit(),
        (None, None) => Ok(()),
    };
    // The reader of the log went away: nothing is wrong, and nothing more is wanted of it.
    let broken_pipe = written
        .as_ref()
        .is_err_and(|e| output::is_broken_pipe(e) && log_target == Some(&Target::Stdout));
    if let Err(e) = written
        && !broken_pipe
    {
        if let Some(target) = stats_target {
            let _ = output::write_target(target, &output.stats_json());
        }
        let target = log_target.expect("only a log fails to be written");
        return Err(cannot_write(target, e));
    }
    if let Some(target) = stats_target {
        output::write_target(target, &output.stats_json()).map_err(|e| cannot_write(target, e))?;
    }
    if broken_pipe {
        return Ok(());
    }
    eprintln!("{}", output.summary());
    if let Some(msg) = stopped {
        return Err((1, format!("{msg} (events up to then were written)")));
    }
    if let Some(stop) = &output.interrupted {
        return Err((
            130,
            format!(
                "{} at t = {}: the log holds every event up to then",
                stop.reason, stop.time
            ),
        ));
    }
    if let Some((spec, dir)) = frames {
        write_frames(&snapshots, &spec, &dir)?;
    }
    Ok(())
}

/// Renders the frames after the log and statistics are safe on disk.
fn write_frames(snapshots: &[Snapshot], spec: &FrameSpec, dir: &Path) -> Result<(), Failure> {
    match render_series(snapshots, spec.width, spec.height, dir) {
        Ok(files) => {
            eprintln!("wrote {} frames to {}", files.len(), dir.display());
            Ok(())
        }
        Err(e) => Err((
            1,
            format!("frames not written: {e} (the event log and statistics were written)"),
        )),
    }
}

fn compare(args: &[String], out: &Path) -> Result<(), Failure> {
    use kinetic_collide_cli::compare::{NamedScene, compare_scene, markdown, write_csv};
    use kinetic_scenes::families::Family;
    let names: Vec<String> = if args.is_empty() {
        Family::ALL.iter().map(|f| f.name().to_string()).collect()
    } else {
        args.to_vec()
    };
    let scenes = names
        .iter()
        .map(|a| NamedScene::load(a))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| (2, e))?;
    std::fs::create_dir_all(out).map_err(|e| (1, format!("{}: {e}", out.display())))?;
    let mut rows = Vec::new();
    for scene in &scenes {
        if scene.scene.response != kinetic_collide::Response::None {
            eprintln!(
                "{}: elastic response, so only the kinetic structures run (time-stepped, rapier \
                 and avian runs would follow other motions and could not be scored contact by contact)",
                scene.name
            );
        }
        rows.extend(compare_scene(scene, |r| {
            eprintln!(
                "{} {} {}: {:.3} s, {} of {} contacts missed, {} false{}",
                r.scene,
                r.method,
                r.step,
                r.wall_seconds,
                r.missed,
                r.contacts,
                r.false_contacts,
                if r.error.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", r.error)
                }
            )
        }));
        // Keep what is done safe after each scene.
        write_csv(&out.join("compare.csv"), &rows).map_err(|e| (1, e))?;
    }
    to_stdout(&markdown(&rows))?;
    kinetic_collide_cli::chart::draw(&rows, &out.join("compare.png"))
        .map_err(|e| (1, format!("chart not drawn: {e} (the CSV was written)")))?;
    eprintln!("wrote {0}/compare.csv and {0}/compare.png", out.display());
    Ok(())
}

fn generate(spheres: HardSpheres, out: Option<&Path>) -> Result<(), Failure> {
    let scene = spheres.build().map_err(|e| (2, e.to_string()))?;
    if !(scene.horizon.is_finite() && scene.horizon > 0.0) {
        return Err((
            2,
            format!(
                "these parameters give no finite horizon (horizon {}): the spheres are too \
                 small for f64",
                scene.horizon
            ),
        ));
    }
    let text = scene.to_json();
    // What is written must read back: a scene `run` would refuse is refused here.
    Scene::from_json(&text).map_err(|e| {
        (
            2,
            format!("these parameters give a scene that cannot run: {e}"),
        )
    })?;
    match out {
        Some(path) => {
            write_whole(path, &text).map_err(|e| (1, format!("{}: {e}", path.display())))?
        }
        None => to_stdout(&text)?,
    }
    let counts: Vec<String> = spheres
        .species()
        .iter()
        .map(|s| format!("{} of diameter {}", s.count, s.diameter))
        .collect();
    eprintln!(
        "{} spheres ({}), {} of side {:.4}, horizon {:.6} for about {} collisions",
        spheres.n,
        counts.join(", "),
        if spheres.periodic {
            "periodic box"
        } else {
            "walls"
        },
        spheres.side(),
        scene.horizon,
        spheres.collisions
    );
    Ok(())
}

fn default_scene() -> Result<(), Failure> {
    let dir = Path::new("out/marbles_on_a_table");
    let scene = BallScene::marbles_on_a_table().build();
    let spec = FrameSpec {
        count: DEFAULT_FRAMES,
        ..FrameSpec::default()
    };
    let (output, snapshots) = match run_with_snapshots(&scene, None, &spec) {
        Ok(out) => out,
        Err(e) => return Err((1, e.to_string())),
    };
    write_run(dir, &scene, &output).map_err(|e| (1, e))?;
    to_stdout(&format!(
        "marbles on a table: {}\nwrote {1}/scene.json, {1}/events.jsonl ({2} events) and \
         {1}/stats.json\n",
        output.summary(),
        dir.display(),
        output.events.len(),
    ))?;
    write_frames(&snapshots, &spec, dir)
}

/// Frames the built-in scene writes.
const DEFAULT_FRAMES: usize = 60;
