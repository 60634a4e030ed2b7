//! Running a scene on the structure the registry ([`crate::Structure`]) names: events
//! processed to the horizon and handed to a sink in batches that end between instants, and
//! the event log and statistics written exactly as the scene format says.

use crate::scene::{Scene, ShapeSpec};
mod spheres;

pub use crate::structures::Slice;
use crate::structures::{FLIGHT_PARTS, Race, build_cost};
use crate::{Structure, World};
use kinetic_core::{ContactEvent, ContactKind, Shape, Stats, WorldError};
use kinetic_flight::ConvexShape;
use kinetic_spheres::{ElasticCells, ListedSpheres};
pub use spheres::{BLOCKS, MeasuredBulk};
use spheres::{InWalls, faster_in_walls, run_cells, run_listed, run_periodic};
use std::cell::RefCell;
use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Why a run could not be done.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Bad input (scene or options): exit status 2, nothing written.
    #[error("{0}")]
    Input(String),
    /// The run stopped part-way (for instance a Zeno configuration); what was computed up
    /// to then is kept.
    #[error("run stopped at t = {time}: {source}")]
    Stopped {
        /// The time reached.
        time: f64,
        /// Why.
        source: WorldError,
        /// The events and statistics computed up to then.
        partial: Box<RunOutput>,
    },
}

impl From<crate::scene::SceneError> for RunError {
    fn from(e: crate::scene::SceneError) -> RunError {
        RunError::Input(e.to_string())
    }
}

impl From<WorldError> for RunError {
    fn from(e: WorldError) -> RunError {
        RunError::Input(e.to_string())
    }
}

impl From<kinetic_flight::ShapeError> for RunError {
    fn from(e: kinetic_flight::ShapeError) -> RunError {
        RunError::Input(e.to_string())
    }
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// The structure used (at the end of the run, when it measured the shortlist).
    pub structure: Structure,
    /// A run without a named structure: which structure ran each slice of it and what each
    /// slice cost, in order (the structures tried, their cost, and when the run switched).
    /// Elastic balls in walls that two structures hold list the trials (the lists', and the
    /// cell grid's where it was tried), each from the start without a log, then the whole
    /// run on the faster. Empty when the structure was named or the scene has one structure
    /// only.
    pub race: Vec<Slice>,
    /// Number of objects.
    pub objects: usize,
    /// The horizon.
    pub horizon: f64,
    /// Contact events in log order: every event of [`run_scene`]; empty after
    /// [`run_scene_streamed`], whose sink took them as they came.
    pub events: Vec<ContactEvent>,
    /// Where the run was stopped before its horizon on request (a signal, or an event sink
    /// that could take no more), and why. The events up to then are complete.
    pub interrupted: Option<Interruption>,
    /// Run statistics.
    pub stats: Stats,
    /// The structure's own figures, by name.
    pub structure_stats: Vec<(&'static str, f64)>,
    /// A periodic run's collision rate, temperature and pressure, with their uncertainty.
    pub bulk: Option<MeasuredBulk>,
    /// Wall-clock seconds of the detection (excluding parsing and writing).
    pub wall_seconds: f64,
}

/// A run stopped before its horizon on request.
#[derive(Clone, Debug, PartialEq)]
pub struct Interruption {
    /// The time reached: every event at or before it was reported, none after.
    pub time: f64,
    /// Why.
    pub reason: String,
}

/// Where a streamed run sends its events, and how it is told to stop.
pub struct Stream<'a> {
    /// Takes each batch of events, in log order (every batch ends at an instant: events at
    /// one time are never split). `Break(reason)` stops the run there.
    pub sink: &'a mut dyn FnMut(&[ContactEvent]) -> ControlFlow<String>,
    /// Set (by a signal handler, say) to stop the run at the next instant.
    pub stop: Option<&'a AtomicBool>,
}

/// Events a run holds at most before it hands them to its sink (memory does not grow with
/// the length of a run).
const BATCH: usize = 4096;

/// What a run drives: a world (any structure), the cell grid or the periodic box.
trait Simulation {
    fn step_to(&mut self, until: f64) -> Result<bool, WorldError>;
    fn next_time(&self) -> f64;
    fn clock(&self) -> f64;
    fn take_events(&mut self) -> Vec<ContactEvent>;
    fn finish(&mut self, horizon: f64) -> Result<(), WorldError>;
}

impl Simulation for World {
    fn step_to(&mut self, until: f64) -> Result<bool, WorldError> {
        Ok(self.step(until)?.is_some())
    }
    fn next_time(&self) -> f64 {
        self.next_event_time()
    }
    fn clock(&self) -> f64 {
        self.now()
    }
    fn take_events(&mut self) -> Vec<ContactEvent> {
        self.drain_events()
    }
    fn finish(&mut self, horizon: f64) -> Result<(), WorldError> {
        self.advance_to(horizon)
    }
}

/// The whole-scene simulators share the world's stepping interface, method for method.
macro_rules! scene_simulation {
    ($($simulation:ty),*) => {$(
        impl Simulation for $simulation {
            fn step_to(&mut self, until: f64) -> Result<bool, WorldError> {
                self.step(until)
            }
            fn next_time(&self) -> f64 {
                self.next_event_time()
            }
            fn clock(&self) -> f64 {
                self.now()
            }
            fn take_events(&mut self) -> Vec<ContactEvent> {
                self.drain_events()
            }
            fn finish(&mut self, horizon: f64) -> Result<(), WorldError> {
                self.advance_to(horizon)
            }
        }
    )*};
}

scene_simulation!(ElasticCells, ListedSpheres);

/// How a drive to a time ended.
enum Reached {
    /// The time was reached.
    Time,
    /// Stopped on request at the simulation's clock.
    Stopped(String),
    /// Paused at the simulation's clock, between two instants, at a wall-clock deadline.
    Deadline,
}

/// Hands the events `sim` holds to the sink.
fn flush(sim: &mut impl Simulation, stream: &mut Stream<'_>) -> ControlFlow<String> {
    let events = sim.take_events();
    if events.is_empty() {
        return ControlFlow::Continue(());
    }
    (stream.sink)(&events)
}

/// Processes `sim`'s events up to `until` and moves its clock there, handing the events
/// to the sink in batches that end at an instant; stops at the next instant once `stop` is
/// set or the sink breaks. On an error the events up to it are handed on first.
fn drive(
    sim: &mut impl Simulation,
    until: f64,
    stream: &mut Stream<'_>,
) -> Result<Reached, WorldError> {
    drive_within(sim, until, stream, None)
}

/// [`drive`], pausing between two instants (its clock at the last event) once the wall clock
/// passes `deadline`, looked at every 64 events.
fn drive_within(
    sim: &mut impl Simulation,
    until: f64,
    stream: &mut Stream<'_>,
    deadline: Option<Instant>,
) -> Result<Reached, WorldError> {
    let mut steps = 0usize;
    let mut looked = 0usize;
    loop {
        let stepped = match sim.step_to(until) {
            Ok(stepped) => stepped,
            Err(e) => {
                let _ = flush(sim, stream);
                return Err(e);
            }
        };
        steps += 1;
        // A batch ends only between instants, so ties stay in (a, b) order across batches.
        if stepped && sim.next_time() <= sim.clock() {
            continue;
        }
        looked += 1;
        if stepped && looked >= 64 {
            looked = 0;
            if deadline.is_some_and(|d| Instant::now() >= d) {
                return Ok(match flush(sim, stream) {
                    ControlFlow::Break(reason) => Reached::Stopped(reason),
                    ControlFlow::Continue(()) => Reached::Deadline,
                });
            }
        }
        let stop = stream.stop.is_some_and(|s| s.load(Ordering::Relaxed));
        if steps >= BATCH || !stepped || stop {
            steps = 0;
            if let ControlFlow::Break(reason) = flush(sim, stream) {
                return Ok(Reached::Stopped(reason));
            }
            if stop {
                return Ok(Reached::Stopped("interrupted by a signal".to_string()));
            }
        }
        if !stepped {
            break;
        }
    }
    sim.finish(until)?;
    Ok(match flush(sim, stream) {
        ControlFlow::Break(reason) => Reached::Stopped(reason),
        ControlFlow::Continue(()) => Reached::Time,
    })
}

/// The world a raced run starts on (the model's pick), its structure and its build's wall
/// seconds.
fn raced_start(scene: &Scene, chosen: Structure) -> Result<(World, Structure, f64), RunError> {
    let built = Instant::now();
    let (world, name) = build_world(scene, Some(chosen))?;
    Ok((world, name, built.elapsed().as_secs_f64()))
}

/// [`drive`] in the race's slices: each slice timed, and the world handed to the structure
/// the race names after it.
fn drive_racing(
    world: &mut World,
    until: f64,
    race: &mut Race,
    horizon: f64,
    stream: &mut Stream<'_>,
) -> Result<Reached, WorldError> {
    loop {
        let from = world.now();
        let planned = race.slice_end(from).min(until);
        let start = Instant::now();
        let deadline = race
            .wall_limit(planned)
            .map(|limit| start + Duration::from_secs_f64(limit));
        let mut reached = drive_within(world, planned, stream, deadline)?;
        let wall = start.elapsed().as_secs_f64();
        // A trial past its wall-clock limit ends its slice where it stands: it has lost.
        let to = match reached {
            Reached::Deadline => {
                reached = Reached::Time;
                world.now()
            }
            _ => planned,
        };
        let stats = world.stats();
        let pairs = stats.events_by_kind.get("collision").copied().unwrap_or(0);
        race.contact_share(pairs as f64 / stats.events_total().max(1) as f64);
        let least_flight = horizon / FLIGHT_PARTS;
        let next = race.slice_done(from, to, wall, &mut |s, worth| {
            build_cost(world, s, least_flight, worth)
        });
        if let Some(next) = next {
            let build = Instant::now();
            world.switch_structure(next, least_flight)?;
            race.switched(build.elapsed().as_secs_f64());
        }
        if !matches!(reached, Reached::Time) || to >= until {
            return Ok(reached);
        }
    }
}

/// Runs a periodic `scene` streamed as [`run_scene_streamed`] does, with its bulk figures
/// measured from `measure_from` to the horizon (the start left out, so that they are the
/// equilibrated fluid's), in [`BLOCKS`] blocks that give their standard errors.
pub fn run_periodic_streamed(
    scene: &Scene,
    measure_from: f64,
    stream: &mut Stream<'_>,
) -> Result<RunOutput, RunError> {
    if scene.periodic.is_none() {
        return Err(RunError::Input(
            "--measure-from: applies to scenes with a periodic box only (their bulk figures)"
                .to_string(),
        ));
    }
    run_periodic(scene, Instant::now(), stream, measure_from)
}

/// Runs `scene` to its horizon with the named structure (or the chosen one), holding every
/// event in the output.
pub fn run_scene(scene: &Scene, structure: Option<Structure>) -> Result<RunOutput, RunError> {
    holding_events(|stream| {
        run_scene_streamed(scene, structure, &[], &mut |_, _| {}, stream).map(|out| (out, ()))
    })
    .map(|(out, ())| out)
}

/// Runs `run` with a stream that holds every event, and puts them in its output (a stopped
/// run's partial output too): a streamed run made whole.
pub fn holding_events<T>(
    run: impl FnOnce(&mut Stream<'_>) -> Result<(RunOutput, T), RunError>,
) -> Result<(RunOutput, T), RunError> {
    let mut events = Vec::new();
    let mut sink = |batch: &[ContactEvent]| {
        events.extend_from_slice(batch);
        ControlFlow::Continue(())
    };
    let result = run(&mut Stream {
        sink: &mut sink,
        stop: None,
    });
    match result {
        Ok((mut output, more)) => {
            output.events = events;
            Ok((output, more))
        }
        Err(RunError::Stopped {
            time,
            source,
            mut partial,
        }) => {
            partial.events = events;
            Err(RunError::Stopped {
                time,
                source,
                partial,
            })
        }
        Err(e) => Err(e),
    }
}

/// Runs `scene` to its horizon with the named structure (or the chosen one), handing its
/// events to `stream`'s sink in log order as they happen, so memory does not grow with the
/// number of events. At each of `times` (increasing, within the horizon) it calls `sample`
/// with the world and, for each object, whether it began a contact since the previous
/// sample. The events are the same as [`run_scene`]'s, bit for bit, samples or not; a stop
/// on request ends the run at an instant and is noted in [`RunOutput::interrupted`].
pub fn run_scene_streamed(
    scene: &Scene,
    structure: Option<Structure>,
    times: &[f64],
    sample: &mut dyn FnMut(&World, &[bool]),
    stream: &mut Stream<'_>,
) -> Result<RunOutput, RunError> {
    let start = Instant::now();
    let chosen = structure.unwrap_or_else(|| Structure::for_scene(scene));
    if scene.periodic.is_some() || chosen == Structure::Periodic {
        if !times.is_empty() {
            return Err(RunError::Input(
                "--frames: frames are drawn from a world, and a periodic scene runs on the \
                 periodic structure only"
                    .to_string(),
            ));
        }
        if chosen != Structure::Periodic || scene.periodic.is_none() {
            return Err(RunError::Input(format!(
                "--structure {}: {}",
                chosen.name(),
                if scene.periodic.is_some() {
                    "a periodic scene runs on the periodic structure only"
                } else {
                    "applies to scenes with a periodic box only"
                }
            )));
        }
        return run_periodic(scene, start, stream, 0.0);
    }
    if matches!(chosen, Structure::Cells | Structure::Lists) {
        if times.is_empty() {
            // Without a name, the two that hold balls in walls are measured.
            let (chosen, trials) = match structure {
                None if chosen == Structure::Lists => faster_in_walls(scene, stream.stop),
                _ if chosen == Structure::Cells => (InWalls::Cells(None), Vec::new()),
                _ => (InWalls::Lists(None), Vec::new()),
            };
            let (chosen, mut output) = match chosen {
                InWalls::Cells(tried) => {
                    (Structure::Cells, run_cells(scene, start, stream, tried)?)
                }
                InWalls::Lists(tried) => {
                    (Structure::Lists, run_listed(scene, start, stream, tried)?)
                }
            };
            if !trials.is_empty() {
                // The winner went on from its trial.
                let tried: f64 = trials.iter().map(|t| t.wall_seconds).sum();
                let from = trials
                    .iter()
                    .filter(|t| t.structure == chosen)
                    .map(|t| t.to)
                    .fold(0.0, f64::max);
                let to = output
                    .interrupted
                    .as_ref()
                    .map_or(scene.horizon, |i| i.time);
                output.race = trials;
                output.race.push(Slice {
                    structure: chosen,
                    from,
                    to,
                    wall_seconds: output.wall_seconds - tried,
                    build_seconds: 0.0,
                });
            }
            return Ok(output);
        }
        if structure.is_none() {
            // Frames are drawn from a world: the grid gives the same events.
            return run_scene_streamed(scene, Some(Structure::Grid), times, sample, stream);
        }
    }
    // Without a named structure the run measures the shortlist as it goes.
    let (mut world, name, build) = match structure {
        Some(named) => {
            let (world, name) = build_world(scene, Some(named))?;
            (world, name, 0.0)
        }
        None => raced_start(scene, chosen)?,
    };
    let mut race = structure.is_none().then(|| Race::new(scene, name, build));
    // Which objects began a contact since the last sample, seen on the way to the sink.
    let begun = RefCell::new(vec![false; if times.is_empty() { 0 } else { world.len() }]);
    let sink = &mut *stream.sink;
    let mut mark = |batch: &[ContactEvent]| {
        let mut begun = begun.borrow_mut();
        for e in batch.iter().filter(|e| e.kind == ContactKind::Begin) {
            for id in [e.a.0, e.b.0] {
                if let Some(b) = begun.get_mut(id as usize) {
                    *b = true;
                }
            }
        }
        sink(batch)
    };
    let mut inner = Stream {
        sink: &mut mark,
        stop: stream.stop,
    };
    let mut take_sample = |world: &World| {
        let mut begun = begun.borrow_mut();
        sample(world, &begun);
        begun.iter_mut().for_each(|b| *b = false);
    };
    // The statistics' first sample is taken at t = 0, as `advance_to` takes it.
    let mut result = world.advance_to(world.now()).map(|()| Reached::Time);
    if result.is_err() {
        let _ = flush(&mut world, &mut inner);
    }
    let mut ends = times
        .iter()
        .copied()
        .filter(|&t| t < scene.horizon)
        .map(|t| (t, true))
        .chain([(
            scene.horizon,
            times.last().is_some_and(|&t| t >= scene.horizon),
        )]);
    while let Ok(Reached::Time) = result {
        let Some((t, sampled)) = ends.next() else {
            break;
        };
        result = match race.as_mut() {
            Some(race) => drive_racing(&mut world, t, race, scene.horizon, &mut inner),
            None => drive(&mut world, t, &mut inner),
        };
        if sampled && matches!(result, Ok(Reached::Time)) {
            take_sample(&world);
        }
    }
    let interrupted = match &result {
        Ok(Reached::Stopped(reason)) => Some(Interruption {
            time: world.now(),
            reason: reason.clone(),
        }),
        _ => None,
    };
    let output = RunOutput {
        structure: race.as_ref().map_or(name, Race::current),
        race: race.map(Race::into_slices).unwrap_or_default(),
        objects: scene.objects.len(),
        horizon: scene.horizon,
        events: Vec::new(),
        interrupted,
        stats: world.stats().clone(),
        structure_stats: world.structure_counters(),
        bulk: None,
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    output.finish(result, world.now())
}

/// The objects' shapes, or the first that cannot be built.
pub fn shapes_of(scene: &Scene) -> Result<Vec<Shape>, RunError> {
    let mut shapes = Vec::with_capacity(scene.objects.len());
    for (i, o) in scene.objects.iter().enumerate() {
        shapes.push(match &o.shape {
            ShapeSpec::Ball { radius } => Shape::Ball { radius: *radius },
            ShapeSpec::Cuboid { half_extents } => ConvexShape::cuboid(*half_extents)
                .map_err(|e| RunError::Input(format!("objects[{i}].shape.cuboid: {e}")))?
                .into_shape(),
            ShapeSpec::ConvexHull { points } => ConvexShape::convex_hull(points)
                .map_err(|e| {
                    RunError::Input(format!("objects[{i}].shape.convex_hull.points: {e}"))
                })?
                .into_shape(),
        });
    }
    Ok(shapes)
}

/// The world of `scene` at t = 0 with the named structure (or the chosen one).
pub fn build_world(
    scene: &Scene,
    structure: Option<Structure>,
) -> Result<(World, Structure), RunError> {
    let shapes = shapes_of(scene)?;
    let name = structure.unwrap_or_else(|| Structure::for_scene(scene));
    if scene.periodic.is_some() {
        return Err(RunError::Input(
            "periodic: a periodic scene runs on the periodic structure, not inside a world \
             (frames and the other structures do not wrap)"
                .to_string(),
        ));
    }
    let mut world = empty_world(scene, name, &shapes)?;
    world
        .add_objects(
            shapes
                .into_iter()
                .zip(scene.objects.iter().map(|o| o.plan())),
        )
        .map_err(|e| RunError::Input(format!("objects: {e}")))?;
    Ok((world, name))
}

/// A world of `scene`'s kind, response and walls on an empty structure `name` sized for
/// `shapes` (the scene's objects).
fn empty_world(scene: &Scene, name: Structure, shapes: &[Shape]) -> Result<World, RunError> {
    let least_flight = scene.horizon / FLIGHT_PARTS;
    let candidates = name
        .build(scene.world, shapes, least_flight)
        .map_err(|why| RunError::Input(format!("--structure {name}: {why}")))?;
    World::with_candidates(scene.world, scene.response, scene.walls, candidates)
        .map_err(|e| RunError::Input(format!("walls: {e}")))
}

/// Appends `e` to `out` as one line of the event log, exactly as the scene format shows it.
pub fn push_event_line(out: &mut String, e: &ContactEvent) {
    let kind = match e.kind {
        ContactKind::Begin => "begin",
        ContactKind::End => "end",
    };
    // The shortest decimal that reads back as the same double (`1.25`, `4.0000000002e-10`);
    // `+ 0.0` turns a -0.0 into 0.0.
    let _ = writeln!(
        out,
        "{{\"t\": {:?}, \"a\": {}, \"b\": {}, \"kind\": \"{kind}\"}}",
        e.time + 0.0,
        e.a.0,
        e.b.0
    );
}

impl RunOutput {
    /// The output of a run that ended at `now` with `result`: stopped runs keep it as partial.
    fn finish(self, result: Result<Reached, WorldError>, now: f64) -> Result<RunOutput, RunError> {
        match result {
            // A paused run reaches here only through a race, which goes on from it.
            Ok(Reached::Time | Reached::Deadline) => Ok(self),
            Ok(Reached::Stopped(reason)) => Ok(RunOutput {
                interrupted: Some(Interruption { time: now, reason }),
                ..self
            }),
            Err(source) => Err(RunError::Stopped {
                time: now,
                source,
                partial: Box::new(self),
            }),
        }
    }

    /// The event log as JSON Lines, exactly as the scene format shows it.
    pub fn event_log(&self) -> String {
        let mut out = String::with_capacity(self.events.len() * 56);
        for e in &self.events {
            push_event_line(&mut out, e);
        }
        out
    }

    /// The statistics as JSON. `wall_seconds` is the only part that differs between runs.
    pub fn stats_json(&self) -> String {
        let s = &self.stats;
        let value = serde_json::json!({
            "structure": self.structure.name(),
            "objects": self.objects,
            "horizon": self.horizon,
            "events": {"total": s.events_total(), "by_kind": s.events_by_kind},
            "certificates": {"max": s.certificates_max, "mean": s.certificates_mean()},
            "candidate_pairs": {"max": s.candidate_pairs_max, "mean": s.candidate_pairs_mean()},
            "contacts": {"begin": s.begins, "end": s.ends},
            "bounces": s.bounces,
            "events_per_contact": s.events_total() as f64 / s.begins.max(1) as f64,
            "structure_stats": self.structure_stats.iter().map(|&(k, v)| (k.to_string(), serde_json::json!(v))).collect::<serde_json::Map<_, _>>(),
            "wall_seconds": self.wall_seconds,
        });
        let mut value = value;
        if let Some(m) = &self.bulk {
            let (b, e) = (&m.bulk, &m.error);
            value["bulk"] = serde_json::json!({
                "collision_rate": b.collision_rate,
                "temperature": b.temperature,
                "pressure": b.pressure,
                "compressibility": b.compressibility,
                "packing": b.packing,
                "from": m.from,
                "blocks": BLOCKS,
                "error": {
                    "collision_rate": e.collision_rate,
                    "pressure": e.pressure,
                    "compressibility": e.compressibility,
                },
            });
        }
        if !self.race.is_empty() {
            value["race"] = self.race_json();
        }
        if let Some(stop) = &self.interrupted {
            value["interrupted"] = serde_json::json!({"time": stop.time, "reason": stop.reason});
        }
        let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
        text.push('\n');
        text
    }

    /// The race as JSON: each run of slices on one structure (a switch starts the next),
    /// with its simulated times, wall seconds and build seconds, and each structure's pace
    /// (wall seconds per unit of simulated time).
    fn race_json(&self) -> serde_json::Value {
        let mut legs: Vec<Slice> = Vec::new();
        for s in &self.race {
            match legs.last_mut() {
                // A leg that starts where the last ended, on the same structure and without
                // a build, continues it (a trial in walls starts afresh, from the start).
                Some(last)
                    if last.structure == s.structure
                        && s.build_seconds == 0.0
                        && s.from == last.to =>
                {
                    last.to = s.to;
                    last.wall_seconds += s.wall_seconds;
                }
                _ => legs.push(s.clone()),
            }
        }
        let legs: Vec<serde_json::Value> = legs
            .iter()
            .map(|l| {
                serde_json::json!({
                    "structure": l.structure.name(),
                    "from": l.from,
                    "to": l.to,
                    "wall_seconds": l.wall_seconds,
                    "build_seconds": l.build_seconds,
                    "pace": (l.wall_seconds - l.build_seconds) / (l.to - l.from).max(f64::MIN_POSITIVE),
                })
            })
            .collect();
        serde_json::json!(legs)
    }

    /// A one-line summary for people.
    pub fn summary(&self) -> String {
        format!(
            "structure {}: {} objects, {} events, {} contacts begun, {} ended, {} bounces, {:.3} s",
            self.structure.name(),
            self.objects,
            self.stats.events_total(),
            self.stats.begins,
            self.stats.ends,
            self.stats.bounces,
            self.wall_seconds
        )
    }
}
