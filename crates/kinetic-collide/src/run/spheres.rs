//! The hard-sphere simulators as whole-scene runs: elastic balls in walls on the cell grid
//! or in neighbour lists, and a periodic box, whose bulk figures are measured over a window of the run that leaves
//! out its start (melting from a lattice, say), in blocks that give their uncertainty.

use super::{Reached, RunError, RunOutput, Simulation, Slice, Stream, drive, drive_within};
use crate::Structure;
use crate::scene::Scene;
use crate::structures::{cell_balls, listed_balls, periodic_balls};
use kinetic_core::{ContactEvent, WorldError};
use kinetic_spheres::{Bulk, ElasticCells, ListedSpheres};
use std::ops::ControlFlow;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// The bulk figures' blocks: the window is cut into this many of equal length, and the
/// figures' uncertainty is the standard error of the block means.
pub const BLOCKS: usize = 10;

/// A periodic run's bulk figures over its measuring window, with their uncertainty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasuredBulk {
    /// The figures over the window (the mean of the blocks' figures, which is the window's
    /// own: the blocks are of equal length and each figure is linear in their sums).
    pub bulk: Bulk,
    /// The standard error of each figure, from the spread of the [`BLOCKS`] block figures
    /// (0 for the temperature and packing, which do not change in an elastic run).
    pub error: Bulk,
    /// The simulated time the window starts at (it ends at the horizon).
    pub from: f64,
}

/// The output of a whole-scene run on `structure`: its statistics and the structure's own
/// counters, its bulk figures, and the wall time since `start` (events go to the stream).
fn whole_run(
    scene: &Scene,
    structure: Structure,
    (stats, structure_stats): (kinetic_core::Stats, Vec<(&'static str, f64)>),
    bulk: Option<MeasuredBulk>,
    start: Instant,
) -> RunOutput {
    RunOutput {
        structure,
        race: Vec::new(),
        objects: scene.objects.len(),
        horizon: scene.horizon,
        events: Vec::new(),
        interrupted: None,
        stats,
        structure_stats,
        bulk,
        wall_seconds: start.elapsed().as_secs_f64(),
    }
}

/// The share of the horizon the trials in walls run at least ([`faster_in_walls`]): shorter
/// trials measure the lists before their shells are first crossed, which at packings of 1%
/// makes them look faster than they are.
const WALLS_TRIAL_SHARE: f64 = 1.0 / 64.0;

/// The most wall seconds the lists' trial runs, for runs so long that their share of the
/// horizon would take longer: a streamed log starts within a few tenths of a second.
const WALLS_TRIAL_WALL: f64 = 0.1;

/// The share of the lists' projected run the cell grid's trial may cost at least (its build
/// and its run to the same time): beyond it the run keeps the lists untried against (short
/// runs, whose builds cost most of them).
const WALLS_TRIAL_BUDGET: f64 = 0.1;

/// A hard-sphere simulator in walls that ran a trial from the start of the run, and the
/// events it found, held for the log.
pub(super) struct Tried<S> {
    pub(super) sim: S,
    pub(super) events: Vec<ContactEvent>,
}

impl<S> Tried<S> {
    /// `tried`, or a simulator built afresh with no events held.
    fn or_fresh(
        tried: Option<Tried<S>>,
        build: impl FnOnce() -> Result<S, RunError>,
    ) -> Result<Tried<S>, RunError> {
        match tried {
            Some(tried) => Ok(tried),
            None => Ok(Tried {
                sim: build()?,
                events: Vec::new(),
            }),
        }
    }
}

/// Which structure runs elastic balls in walls, and the trial that won, to go on from.
pub(super) enum InWalls {
    Lists(Option<Tried<ListedSpheres>>),
    Cells(Option<Tried<ElasticCells>>),
}

/// Elastic balls in walls that the neighbour lists and the cell grid both hold (sizes within a
/// factor of two): which of the two runs `scene` faster, measured, and the two trials as
/// slices. The lists spend the least per collision where the spheres crowd; where they are
/// sparse, a sphere's shell holds few neighbours and it crosses it often, and the cell grid
/// can be twice as fast (measured: 125 and 251 spheres at packings 0.024 and 0.010).
///
/// Each trial runs from the start of the run, its events held: the lists over
/// [`WALLS_TRIAL_SHARE`] of the horizon, and on until they have run as long as their build
/// took (a run much shorter than its build could not pay back another), within the first of
/// the bulk figures' [`BLOCKS`] and [`WALLS_TRIAL_WALL`] seconds, then, where that costs at most [`WALLS_TRIAL_BUDGET`] of the lists'
/// projected run, the cell grid to the same time, stopped once its run has taken as long as
/// the lists'. Each projects its whole run, its build and its pace over the horizon. The
/// winner goes on from where its trial stopped, its held events first in the log (every
/// structure gives the same log), so a trial costs only the loser's. A trial that fails, or a
/// `stop` set meanwhile, leaves the lists, built afresh.
pub(super) fn faster_in_walls(scene: &Scene, stop: Option<&AtomicBool>) -> (InWalls, Vec<Slice>) {
    let (Some((walls, balls)), Some(_)) = (listed_balls(scene), cell_balls(scene)) else {
        return (InWalls::Lists(None), Vec::new());
    };
    let horizon = scene.horizon;
    let slice = |structure, to: f64, wall: f64, build: f64| Slice {
        structure,
        from: 0.0,
        to,
        wall_seconds: wall + build,
        build_seconds: build,
    };
    let built = Instant::now();
    let Ok(mut gas) = ListedSpheres::in_walls(walls, &balls) else {
        return (InWalls::Lists(None), Vec::new());
    };
    let lists_build = built.elapsed().as_secs_f64();
    let run = Instant::now();
    let least = horizon * WALLS_TRIAL_SHARE;
    // Within the bulk figures' first block, which the winner's run goes on summing.
    let first_block = horizon / BLOCKS as f64;
    let mut events = Vec::new();
    let Some(mut to) = trial(&mut gas, least, WALLS_TRIAL_WALL, stop, &mut events) else {
        return (InWalls::Lists(None), Vec::new());
    };
    let wall = run.elapsed().as_secs_f64();
    if to >= least && wall < lists_build.min(WALLS_TRIAL_WALL) {
        match trial(
            &mut gas,
            first_block,
            lists_build.min(WALLS_TRIAL_WALL) - wall,
            stop,
            &mut events,
        ) {
            Some(reached) => to = reached,
            None => return (InWalls::Lists(None), Vec::new()),
        }
    }
    let lists_wall = run.elapsed().as_secs_f64();
    let lists = Tried { sim: gas, events };
    let mut trials = vec![slice(Structure::Lists, to, lists_wall, lists_build)];
    // The cell grid's build is about half the lists' (measured at 125 to 32,000 spheres).
    let lists_run = lists_build + lists_wall / to.max(f64::MIN_POSITIVE) * horizon;
    if 0.5 * lists_build + lists_wall > WALLS_TRIAL_BUDGET * lists_run {
        return (InWalls::Lists(Some(lists)), trials);
    }
    let built = Instant::now();
    let Ok(mut cells) = ElasticCells::new(walls, &balls) else {
        return (InWalls::Lists(Some(lists)), trials);
    };
    let cells_build = built.elapsed().as_secs_f64();
    let run = Instant::now();
    let mut events = Vec::new();
    // Slower over the same span than the lists, the cell grid has lost.
    let Some(reached) = trial(&mut cells, to, lists_wall, stop, &mut events) else {
        return (InWalls::Lists(Some(lists)), trials);
    };
    trials.push(slice(
        Structure::Cells,
        reached,
        run.elapsed().as_secs_f64(),
        cells_build,
    ));
    let projected = |t: &Slice| {
        let pace = (t.wall_seconds - t.build_seconds) / t.to.max(f64::MIN_POSITIVE);
        t.build_seconds + pace * horizon
    };
    if projected(&trials[1]) < projected(&trials[0]) {
        (InWalls::Cells(Some(Tried { sim: cells, events })), trials)
    } else {
        (InWalls::Lists(Some(lists)), trials)
    }
}

/// Runs `sim` until `until` or for `wall` seconds ([`drive_within`]), whichever comes first,
/// its events added to `events`; the time it reached, or `None` when it failed or `stop` was
/// set.
fn trial(
    sim: &mut impl Simulation,
    until: f64,
    wall: f64,
    stop: Option<&AtomicBool>,
    events: &mut Vec<ContactEvent>,
) -> Option<f64> {
    let mut hold = |batch: &[ContactEvent]| {
        events.extend_from_slice(batch);
        ControlFlow::Continue(())
    };
    let mut held = Stream {
        sink: &mut hold,
        stop,
    };
    let deadline = Instant::now() + Duration::from_secs_f64(wall);
    match drive_within(sim, until, &mut held, Some(deadline)) {
        Ok(Reached::Time) => Some(until),
        Ok(Reached::Deadline) => Some(sim.clock()),
        _ => None,
    }
}

/// Runs a scene on the cell grid (going on from `tried`, when given, the grid of a trial from
/// the start), with the bulk figures of the whole run (the pressure is that on the walls).
pub(super) fn run_cells(
    scene: &Scene,
    start: Instant,
    stream: &mut Stream<'_>,
    tried: Option<Tried<ElasticCells>>,
) -> Result<RunOutput, RunError> {
    let (walls, balls) = cell_balls(scene).ok_or_else(|| {
        RunError::Input(
            "--structure cells: applies to elastic balls moving linearly inside walls in a \
             \"free\" world, with sizes the grid can hold"
                .to_string(),
        )
    })?;
    let Tried {
        sim: mut cells,
        events: held,
    } = Tried::or_fresh(tried, || {
        ElasticCells::new(walls, &balls).map_err(|e| RunError::Input(format!("objects: {e}")))
    })?;
    let (result, measured) = go_on(&mut cells, &held, scene.horizon, stream);
    let output = whole_run(
        scene,
        Structure::Cells,
        (cells.stats().clone(), cells.counters()),
        measured,
        start,
    );
    output.finish(result, cells.now())
}

/// Runs a scene of elastic balls of similar sizes in walls on neighbour lists (going on from
/// `tried`, when given, the lists of a trial from the start), with the bulk figures of the
/// whole run (the pressure is that on the walls).
pub(super) fn run_listed(
    scene: &Scene,
    start: Instant,
    stream: &mut Stream<'_>,
    tried: Option<Tried<ListedSpheres>>,
) -> Result<RunOutput, RunError> {
    let (walls, balls) = listed_balls(scene).ok_or_else(|| {
        RunError::Input(
            "--structure lists: applies to elastic balls moving linearly inside walls in a \
             \"free\" world, the largest at most twice the smallest"
                .to_string(),
        )
    })?;
    let Tried {
        sim: mut gas,
        events: held,
    } = Tried::or_fresh(tried, || {
        ListedSpheres::in_walls(walls, &balls).map_err(|e| RunError::Input(format!("objects: {e}")))
    })?;
    let (result, measured) = go_on(&mut gas, &held, scene.horizon, stream);
    let output = whole_run(
        scene,
        Structure::Lists,
        (gas.stats(), gas.counters()),
        measured,
        start,
    );
    output.finish(result, gas.now())
}

/// Runs a scene in a periodic box, measuring its bulk figures from `measure_from` (0: the
/// whole run) to the horizon.
pub(super) fn run_periodic(
    scene: &Scene,
    start: Instant,
    stream: &mut Stream<'_>,
    measure_from: f64,
) -> Result<RunOutput, RunError> {
    let (cell, balls) = periodic_balls(scene).ok_or_else(|| {
        RunError::Input(
            "--structure periodic: applies to elastic balls moving linearly in a periodic box"
                .to_string(),
        )
    })?;
    if !(measure_from >= 0.0 && measure_from < scene.horizon) {
        return Err(RunError::Input(format!(
            "--measure-from {measure_from}: must be at least 0 and before the horizon ({})",
            scene.horizon
        )));
    }
    let mut gas = ListedSpheres::periodic(cell, &balls)
        .map_err(|e| RunError::Input(format!("objects: {e}")))?;
    let (result, measured) = measure(&mut gas, scene.horizon, measure_from, stream);
    let output = whole_run(
        scene,
        Structure::Periodic,
        (gas.stats(), gas.counters()),
        measured,
        start,
    );
    output.finish(result, gas.now())
}

/// A hard-sphere simulator that sums bulk figures as it runs.
trait Measured: Simulation {
    fn reset_bulk(&mut self);
    fn bulk(&self) -> Bulk;
}

impl Measured for ListedSpheres {
    fn reset_bulk(&mut self) {
        ListedSpheres::reset_bulk(self)
    }
    fn bulk(&self) -> Bulk {
        ListedSpheres::bulk(self)
    }
}

impl Measured for ElasticCells {
    fn reset_bulk(&mut self) {
        ElasticCells::reset_bulk(self)
    }
    fn bulk(&self) -> Bulk {
        ElasticCells::bulk(self)
    }
}

/// [`measure`] over the whole run for a simulator in walls that may have run a trial from
/// the start: the events it held go to the log first.
fn go_on(
    gas: &mut impl Measured,
    held: &[ContactEvent],
    horizon: f64,
    stream: &mut Stream<'_>,
) -> (Result<Reached, WorldError>, Option<MeasuredBulk>) {
    // They end at an instant: a trial pauses between two.
    if !held.is_empty()
        && let ControlFlow::Break(reason) = (stream.sink)(held)
    {
        return (Ok(Reached::Stopped(reason)), None);
    }
    measure(gas, horizon, 0.0, stream)
}

/// Drives `gas` to `horizon`, its bulk figures taken afresh at `from` and over each of
/// [`BLOCKS`] equal blocks from there; `None` for the figures when the run stopped first.
fn measure(
    gas: &mut impl Measured,
    horizon: f64,
    from: f64,
    stream: &mut Stream<'_>,
) -> (Result<Reached, WorldError>, Option<MeasuredBulk>) {
    if from > 0.0 {
        match drive(gas, from, stream) {
            Ok(Reached::Time) => {}
            other => return (other, None),
        }
    }
    let mut blocks = Vec::with_capacity(BLOCKS);
    for k in 1..=BLOCKS {
        // From the start, the first block's figures are those summed since it (a trial's
        // included).
        if k > 1 || from > 0.0 {
            gas.reset_bulk();
        }
        let end = if k == BLOCKS {
            horizon
        } else {
            from + (horizon - from) * k as f64 / BLOCKS as f64
        };
        match drive(gas, end, stream) {
            Ok(Reached::Time) => blocks.push(gas.bulk()),
            other => return (other, None),
        }
    }
    (Ok(Reached::Time), Some(combine(&blocks, from)))
}

/// The mean and standard error of the blocks' figures.
fn combine(blocks: &[Bulk], from: f64) -> MeasuredBulk {
    let n = blocks.len() as f64;
    let stat = |f: fn(&Bulk) -> f64| {
        let mean = blocks.iter().map(f).sum::<f64>() / n;
        let var = blocks.iter().map(|b| (f(b) - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        (mean, (var / n).sqrt())
    };
    let (rate, rate_err) = stat(|b| b.collision_rate);
    let (pressure, pressure_err) = stat(|b| b.pressure);
    let (z, z_err) = stat(|b| b.compressibility);
    let last = blocks[blocks.len() - 1];
    MeasuredBulk {
        bulk: Bulk {
            collision_rate: rate,
            pressure,
            compressibility: z,
            ..last
        },
        error: Bulk {
            collision_rate: rate_err,
            temperature: 0.0,
            pressure: pressure_err,
            compressibility: z_err,
            packing: 0.0,
        },
        from,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_give_their_mean_and_standard_error() {
        let block = |rate: f64| Bulk {
            collision_rate: rate,
            temperature: 1.0,
            pressure: 2.0 * rate,
            compressibility: rate,
            packing: 0.3,
        };
        let m = combine(&[block(1.0), block(2.0), block(3.0)], 5.0);
        assert_eq!(m.bulk.collision_rate, 2.0);
        assert_eq!(m.bulk.pressure, 4.0);
        assert_eq!(m.bulk.packing, 0.3);
        // Sample standard deviation 1 over three blocks.
        assert!((m.error.collision_rate - 1.0 / 3f64.sqrt()).abs() < 1e-15);
        assert!((m.error.pressure - 2.0 / 3f64.sqrt()).abs() < 1e-15);
        assert_eq!(m.error.temperature, 0.0);
        assert_eq!(m.from, 5.0);
    }
}
