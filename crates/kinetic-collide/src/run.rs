//! Running a scene: choose the structure, process events to the horizon, and write the event
//! log and statistics exactly as the scene format says.

use crate::scene::{Scene, ShapeSpec};
use kinetic_core::{
    BruteForce, CandidateStructure, ContactEvent, ContactKind, ElasticCells, FlightPlan, Response,
    Shape, Stats, Walls, World, WorldError, WorldKind,
};
use kinetic_flight::{Choice, ConvexShape, Grid, Guards, LooseGrid, Sweep};
use kinetic_rolling::{ListLayout, RollingTree};
use std::cell::RefCell;
use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// The kinetic structures, by their command-line names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StructureName {
    /// Collision tree with threshold boxes (Section 2), plane worlds.
    RollingTree,
    /// The rolling tree with two global sorted lists (the paper's second remark).
    RollingGlobalLists,
    /// Sweep over boxes of similar-size objects (Section 3.1).
    Sweep,
    /// Guards and cones for arbitrary sizes (Section 3.2).
    Guards,
    /// The sweep's box pairs, found in a hierarchical kinetic grid (neighbours only).
    Grid,
    /// A loose kinetic grid: each object holds a region its box stays in for a while, and
    /// candidates are the objects whose regions overlap (one certificate per object).
    LooseGrid,
    /// Elastic balls in walls on a hierarchical grid of cells, one scheduled event per ball
    /// (the hard-sphere systems of molecular dynamics).
    Cells,
    /// One certificate per pair: the exact reference.
    BruteForce,
}

impl StructureName {
    /// Every name, as written on the command line.
    pub const ALL: [(&'static str, StructureName); 8] = [
        ("rolling-tree", StructureName::RollingTree),
        ("rolling-global-lists", StructureName::RollingGlobalLists),
        ("sweep", StructureName::Sweep),
        ("guards", StructureName::Guards),
        ("grid", StructureName::Grid),
        ("loose-grid", StructureName::LooseGrid),
        ("cells", StructureName::Cells),
        ("brute-force", StructureName::BruteForce),
    ];

    /// Parses a command-line name.
    pub fn parse(name: &str) -> Result<StructureName, RunError> {
        Self::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, s)| *s)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(n, _)| *n).collect();
                RunError::Input(format!(
                    "--structure: unknown structure {name:?} (expected one of: {})",
                    names.join(", ")
                ))
            })
    }

    /// Whether the structure runs `scene` (its world, shapes, response and walls).
    pub fn applies_to(self, scene: &Scene) -> bool {
        match self {
            StructureName::BruteForce => true,
            StructureName::RollingTree | StructureName::RollingGlobalLists => {
                scene.world == WorldKind::Plane
            }
            StructureName::Sweep | StructureName::Grid | StructureName::LooseGrid => true,
            StructureName::Guards => scene.world == WorldKind::Free,
            StructureName::Cells => cells_hold(scene),
        }
    }

    /// The command-line name.
    pub fn as_str(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(_, s)| *s == self)
            .map_or("?", |(n, _)| n)
    }
}

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
    /// The structure used.
    pub structure: StructureName,
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

/// The two engines a run drives: a world (any structure) and the cell grid.
trait Engine {
    fn step_to(&mut self, until: f64) -> Result<bool, WorldError>;
    fn next_time(&self) -> f64;
    fn clock(&self) -> f64;
    fn take_events(&mut self) -> Vec<ContactEvent>;
    fn finish(&mut self, horizon: f64) -> Result<(), WorldError>;
}

impl Engine for World {
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

impl Engine for ElasticCells {
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

/// How a drive to a time ended.
enum Reached {
    /// The time was reached.
    Time,
    /// Stopped on request at the engine's clock.
    Stopped(String),
}

/// Hands the events `engine` holds to the sink.
fn flush(engine: &mut impl Engine, stream: &mut Stream<'_>) -> ControlFlow<String> {
    let events = engine.take_events();
    if events.is_empty() {
        return ControlFlow::Continue(());
    }
    (stream.sink)(&events)
}

/// Processes `engine`'s events up to `until` and moves its clock there, handing the events
/// to the sink in batches that end at an instant; stops at the next instant once `stop` is
/// set or the sink breaks. On an error the events up to it are handed on first.
fn drive(
    engine: &mut impl Engine,
    until: f64,
    stream: &mut Stream<'_>,
) -> Result<Reached, WorldError> {
    let mut steps = 0usize;
    loop {
        let stepped = match engine.step_to(until) {
            Ok(stepped) => stepped,
            Err(e) => {
                let _ = flush(engine, stream);
                return Err(e);
            }
        };
        steps += 1;
        // A batch ends only between instants, so ties stay in (a, b) order across batches.
        if stepped && engine.next_time() <= engine.clock() {
            continue;
        }
        let stop = stream.stop.is_some_and(|s| s.load(Ordering::Relaxed));
        if steps >= BATCH || !stepped || stop {
            steps = 0;
            if let ControlFlow::Break(reason) = flush(engine, stream) {
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
    engine.finish(until)?;
    Ok(match flush(engine, stream) {
        ControlFlow::Break(reason) => Reached::Stopped(reason),
        ControlFlow::Continue(()) => Reached::Time,
    })
}

/// The structure a scene gets when none is named: the lightest one that is exact for it.
/// Elastic balls moving linearly inside walls get the cell grid ([`ElasticCells`]) when it
/// fits their sizes; otherwise a plane world gets the rolling collision tree, and a free world
/// the sweep over boxes when its inner radii differ by at most [`kinetic_flight::SIGMA_MAX`],
/// guards otherwise.
pub fn choose_structure(scene: &Scene) -> StructureName {
    choose_for(scene, &shapes_of(scene).unwrap_or_default())
}

/// [`choose_structure`] for a scene whose shapes are built.
fn choose_for(scene: &Scene, shapes: &[Shape]) -> StructureName {
    if cell_balls(scene).is_some() {
        return StructureName::Cells;
    }
    match scene.world {
        WorldKind::Plane => StructureName::RollingTree,
        WorldKind::Free if kinetic_flight::choose(shapes) == Choice::Guards => {
            StructureName::Guards
        }
        WorldKind::Free => StructureName::Sweep,
    }
}

/// The walls and balls of a scene that the cell grid holds: elastic, free, walls, balls only,
/// no accelerations, and sizes for which the grid is small.
fn cell_balls(scene: &Scene) -> Option<(Walls, Vec<(f64, FlightPlan)>)> {
    let walls = scene.walls?;
    if scene.world != WorldKind::Free || scene.response != Response::Elastic {
        return None;
    }
    let mut balls = Vec::with_capacity(scene.objects.len());
    for o in &scene.objects {
        match o.shape {
            ShapeSpec::Ball { radius } if o.acceleration == glam::DVec3::ZERO => {
                balls.push((radius, o.plan()));
            }
            _ => return None,
        }
    }
    let radii: Vec<f64> = balls.iter().map(|b| b.0).collect();
    ElasticCells::supports(&walls, &radii).then_some((walls, balls))
}

/// Whether the cell grid holds the scene (elastic balls moving linearly inside walls, in a
/// free world, with sizes for which the grid is small).
pub fn cells_hold(scene: &Scene) -> bool {
    cell_balls(scene).is_some()
}

/// Runs a scene on the cell grid.
fn run_cells(
    scene: &Scene,
    start: Instant,
    stream: &mut Stream<'_>,
) -> Result<RunOutput, RunError> {
    let (walls, balls) = cell_balls(scene).ok_or_else(|| {
        RunError::Input(
            "--structure cells: applies to elastic balls moving linearly inside walls in a \
             \"free\" world, with sizes the grid can hold"
                .to_string(),
        )
    })?;
    let mut cells =
        ElasticCells::new(walls, &balls).map_err(|e| RunError::Input(format!("objects: {e}")))?;
    let result = drive(&mut cells, scene.horizon, stream);
    let output = RunOutput {
        structure: StructureName::Cells,
        objects: scene.objects.len(),
        horizon: scene.horizon,
        events: Vec::new(),
        interrupted: None,
        stats: cells.stats().clone(),
        structure_stats: cells.counters(),
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    output.finish(result, cells.now())
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

fn make_structure(
    scene: &Scene,
    shapes: &[Shape],
    name: StructureName,
) -> Result<Box<dyn CandidateStructure>, RunError> {
    match name {
        StructureName::BruteForce => Ok(Box::new(BruteForce::new())),
        StructureName::RollingTree if scene.world == WorldKind::Plane => {
            Ok(Box::new(RollingTree::new(ListLayout::PerNode)))
        }
        StructureName::RollingGlobalLists if scene.world == WorldKind::Plane => {
            Ok(Box::new(RollingTree::new(ListLayout::Global)))
        }
        StructureName::RollingTree | StructureName::RollingGlobalLists => {
            Err(RunError::Input(format!(
                "--structure {}: applies to \"plane\" worlds only",
                name.as_str()
            )))
        }
        // A ball rolling on the plane touches another at a distance of 2 sqrt(ra rb), at
        // most ra + rb: the discs' boxes hold every contact, so the box structures serve.
        StructureName::Guards if scene.world == WorldKind::Plane => Err(RunError::Input(format!(
            "--structure {}: applies to \"free\" worlds only",
            name.as_str()
        ))),
        StructureName::Sweep => Ok(Box::new(Sweep::new())),
        StructureName::Grid => Ok(Box::new(Grid::new())),
        StructureName::LooseGrid => Ok(Box::new(LooseGrid::new())),
        StructureName::Guards => Ok(Box::new(Guards::new(kinetic_flight::guard_fatness(shapes)))),
        StructureName::Cells => Err(RunError::Input(
            "--structure cells: the cell grid runs whole scenes, not inside a world; \
             frames are drawn from a world (use --structure grid)"
                .to_string(),
        )),
    }
}

/// The world of `scene` at t = 0 with the named structure (or the chosen one).
pub fn build_world(
    scene: &Scene,
    structure: Option<StructureName>,
) -> Result<(World, StructureName), RunError> {
    let shapes = shapes_of(scene)?;
    let name = structure.unwrap_or_else(|| choose_for(scene, &shapes));
    let mut world = World::with_structure(
        scene.world,
        scene.response,
        scene.walls,
        make_structure(scene, &shapes, name)?,
    )
    .map_err(|e| RunError::Input(format!("walls: {e}")))?;
    world
        .add_objects(
            shapes
                .into_iter()
                .zip(scene.objects.iter().map(|o| o.plan())),
        )
        .map_err(|e| RunError::Input(format!("objects: {e}")))?;
    Ok((world, name))
}

/// Runs `scene` to its horizon with the named structure (or the chosen one), holding every
/// event in the output.
pub fn run_scene(scene: &Scene, structure: Option<StructureName>) -> Result<RunOutput, RunError> {
    let mut events = Vec::new();
    let mut sink = |batch: &[ContactEvent]| {
        events.extend_from_slice(batch);
        ControlFlow::Continue(())
    };
    let mut stream = Stream {
        sink: &mut sink,
        stop: None,
    };
    let result = run_scene_streamed(scene, structure, &[], &mut |_, _| {}, &mut stream);
    match result {
        Ok(mut output) => {
            output.events = events;
            Ok(output)
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
    structure: Option<StructureName>,
    times: &[f64],
    sample: &mut dyn FnMut(&World, &[bool]),
    stream: &mut Stream<'_>,
) -> Result<RunOutput, RunError> {
    let start = Instant::now();
    let chosen = structure.unwrap_or_else(|| choose_structure(scene));
    if chosen == StructureName::Cells {
        if times.is_empty() {
            return run_cells(scene, start, stream);
        }
        if structure.is_none() {
            // Frames are drawn from a world: the grid gives the same events.
            return run_scene_streamed(scene, Some(StructureName::Grid), times, sample, stream);
        }
    }
    let (mut world, name) = build_world(scene, structure)?;
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
        result = drive(&mut world, t, &mut inner);
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
        structure: name,
        objects: scene.objects.len(),
        horizon: scene.horizon,
        events: Vec::new(),
        interrupted,
        stats: world.stats().clone(),
        structure_stats: world.structure_counters(),
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    output.finish(result, world.now())
}

/// Appends `e` to `out` as one line of the event log, exactly as the scene format shows it.
pub fn push_event_line(out: &mut String, e: &ContactEvent) {
    let kind = match e.kind {
        ContactKind::Begin => "begin",
        ContactKind::End => "end",
    };
    // `+ 0.0` turns a -0.0 into 0.0.
    let _ = writeln!(
        out,
        "{{\"t\": {:.10}, \"a\": {}, \"b\": {}, \"kind\": \"{kind}\"}}",
        e.time + 0.0,
        e.a.0,
        e.b.0
    );
}

impl RunOutput {
    /// The output of a run that ended at `now` with `result`: stopped runs keep it as partial.
    fn finish(self, result: Result<Reached, WorldError>, now: f64) -> Result<RunOutput, RunError> {
        match result {
            Ok(Reached::Time) => Ok(self),
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
            "structure": self.structure.as_str(),
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
        if let Some(stop) = &self.interrupted {
            value["interrupted"] = serde_json::json!({"time": stop.time, "reason": stop.reason});
        }
        let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
        text.push('\n');
        text
    }

    /// A one-line summary for people.
    pub fn summary(&self) -> String {
        format!(
            "structure {}: {} objects, {} events, {} contacts begun, {} ended, {} bounces, {:.3} s",
            self.structure.as_str(),
            self.objects,
            self.stats.events_total(),
            self.stats.begins,
            self.stats.ends,
            self.stats.bounces,
            self.wall_seconds
        )
    }
}
