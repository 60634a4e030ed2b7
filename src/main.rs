//! The `kinetic-collide` command-line tool: runs a scene file and writes its exact event log.

use clap::{Parser, Subcommand};
use kinetic_collide::run::{RunError, RunOutput, StructureName, run_scene, write_whole};
use kinetic_collide::scene::Scene;
use kinetic_collide::scenes::BallScene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Exact kinetic collision detection for moving objects.
///
/// With no command, runs the built-in scene (marbles on a table) and writes its scene, event
/// log and statistics under out/marbles_on_a_table/.
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
        /// Where to write the event log (default: standard output).
        #[arg(long)]
        events: Option<PathBuf>,
        /// Where to write the statistics (JSON).
        #[arg(long)]
        stats: Option<PathBuf>,
        /// The kinetic structure: rolling-tree, rolling-global-lists, sweep, guards or
        /// brute-force (default: chosen from the scene).
        #[arg(long)]
        structure: Option<String>,
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
        Some(Command::Run {
            scene,
            events,
            stats,
            structure,
        }) => run_file(
            &scene,
            events.as_deref(),
            stats.as_deref(),
            structure.as_deref(),
        ),
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

fn run_file(
    path: &Path,
    events: Option<&Path>,
    stats: Option<&Path>,
    structure: Option<&str>,
) -> Result<(), Failure> {
    let structure = structure
        .map(StructureName::parse)
        .transpose()
        .map_err(|e| (2, e.to_string()))?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| (2, format!("{}: cannot read: {e}", path.display())))?;
    let scene = Scene::from_json(&text).map_err(|e| (2, format!("{}: {e}", path.display())))?;
    let (output, stopped) = match run_scene(&scene, structure) {
        Ok(out) => (out, None),
        Err(RunError::Input(msg)) => return Err((2, format!("{}: {msg}", path.display()))),
        Err(RunError::Stopped {
            time,
            source,
            partial,
        }) => (
            *partial,
            Some(format!("run stopped at t = {time}: {source}")),
        ),
    };
    write_outputs(&output, events, stats)?;
    eprintln!("{}", output.summary());
    match stopped {
        Some(msg) => Err((1, format!("{msg} (events up to then were written)"))),
        None => Ok(()),
    }
}

fn write_outputs(
    output: &RunOutput,
    events: Option<&Path>,
    stats: Option<&Path>,
) -> Result<(), Failure> {
    let io = |p: &Path, e: std::io::Error| (1, format!("{}: cannot write: {e}", p.display()));
    match events {
        Some(p) => write_whole(p, &output.event_log()).map_err(|e| io(p, e))?,
        None => print!("{}", output.event_log()),
    }
    if let Some(p) = stats {
        write_whole(p, &output.stats_json()).map_err(|e| io(p, e))?;
    }
    Ok(())
}

fn default_scene() -> Result<(), Failure> {
    let dir = Path::new("out/marbles_on_a_table");
    let scene = BallScene::marbles_on_a_table().build();
    let output = match run_scene(&scene, None) {
        Ok(out) => out,
        Err(e) => return Err((1, e.to_string())),
    };
    let io = |p: &Path, e: std::io::Error| (1, format!("{}: cannot write: {e}", p.display()));
    let scene_path = dir.join("scene.json");
    write_whole(&scene_path, &scene.to_json()).map_err(|e| io(&scene_path, e))?;
    let (events, stats) = (dir.join("events.jsonl"), dir.join("stats.json"));
    write_outputs(&output, Some(&events), Some(&stats))?;
    println!("marbles on a table: {}", output.summary());
    println!(
        "wrote {}, {} ({} events) and {}",
        scene_path.display(),
        events.display(),
        output.events.len(),
        stats.display()
    );
    Ok(())
}
