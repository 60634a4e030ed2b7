//! Running a scene: choose the structure, process events to the horizon, and write the event
//! log and statistics exactly as the scene format says.

use crate::scene::{Scene, ShapeSpec};
use kinetic_core::{
    BruteForce, CandidateStructure, ContactEvent, ContactKind, ElasticCells, FlightPlan, Response,
    Shape, Stats, Walls, World, WorldError, WorldKind,
};
use kinetic_flight::{Choice, ConvexShape, Grid, Guards, Sweep};
use kinetic_rolling::{ListLayout, RollingTree};
use std::fmt::Write as _;
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
    /// Elastic balls in walls on a hierarchical grid of cells, one scheduled event per ball
    /// (the hard-sphere systems of molecular dynamics).
    Cells,
    /// One certificate per pair: the exact reference.
    BruteForce,
}

impl StructureName {
    /// Every name, as written on the command line.
    pub const ALL: [(&'static str, StructureName); 7] = [
        ("rolling-tree", StructureName::RollingTree),
        ("rolling-global-lists", StructureName::RollingGlobalLists),
        ("sweep", StructureName::Sweep),
        ("guards", StructureName::Guards),
        ("grid", StructureName::Grid),
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

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// The structure used.
    pub structure: StructureName,
    /// Number of objects.
    pub objects: usize,
    /// The horizon.
    pub horizon: f64,
    /// Contact events in log order.
    pub events: Vec<ContactEvent>,
    /// Run statistics.
    pub stats: Stats,
    /// The structure's own figures, by name.
    pub structure_stats: Vec<(&'static str, f64)>,
    /// Wall-clock seconds of the detection (excluding parsing and writing).
    pub wall_seconds: f64,
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
fn run_cells(scene: &Scene, start: Instant) -> Result<RunOutput, RunError> {
    let (walls, balls) = cell_balls(scene).ok_or_else(|| {
        RunError::Input(
            "--structure cells: applies to elastic balls moving linearly inside walls in a \
             \"free\" world, with sizes the grid can hold"
                .to_string(),
        )
    })?;
    let mut cells =
        ElasticCells::new(walls, &balls).map_err(|e| RunError::Input(format!("objects: {e}")))?;
    let result = cells.advance_to(scene.horizon);
    let output = RunOutput {
        structure: StructureName::Cells,
        objects: scene.objects.len(),
        horizon: scene.horizon,
        events: cells.drain_events(),
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
        StructureName::Sweep | StructureName::Guards | StructureName::Grid
            if scene.world == WorldKind::Plane =>
        {
            Err(RunError::Input(format!(
                "--structure {}: applies to \"free\" worlds only",
                name.as_str()
            )))
        }
        StructureName::Sweep => Ok(Box::new(Sweep::new())),
        StructureName::Grid => Ok(Box::new(Grid::new())),
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

/// Runs `scene` to its horizon with the named structure (or the chosen one).
pub fn run_scene(scene: &Scene, structure: Option<StructureName>) -> Result<RunOutput, RunError> {
    run_scene_sampled(scene, structure, &[], |_, _| {})
}

/// [`run_scene`], stopping at each of `times` (increasing, within the horizon) to call
/// `sample` with the world at that time and the events since the previous sample. The
/// output is the same as without samples, bit for bit.
pub fn run_scene_sampled(
    scene: &Scene,
    structure: Option<StructureName>,
    times: &[f64],
    mut sample: impl FnMut(&World, &[ContactEvent]),
) -> Result<RunOutput, RunError> {
    let start = Instant::now();
    let chosen = structure.unwrap_or_else(|| choose_structure(scene));
    if chosen == StructureName::Cells {
        if times.is_empty() {
            return run_cells(scene, start);
        }
        if structure.is_none() {
            // Frames are drawn from a world: the grid gives the same events.
            return run_scene_sampled(scene, Some(StructureName::Grid), times, sample);
        }
    }
    let (mut world, name) = build_world(scene, structure)?;
    let mut events = Vec::new();
    let mut result = Ok(());
    for &t in times.iter().filter(|&&t| t < scene.horizon) {
        result = world.advance_to(t);
        let seen = events.len();
        events.extend(world.drain_events());
        if result.is_err() {
            break;
        }
        sample(&world, &events[seen..]);
    }
    if result.is_ok() {
        result = world.advance_to(scene.horizon);
        let seen = events.len();
        events.extend(world.drain_events());
        if result.is_ok() && times.last().is_some_and(|&t| t >= scene.horizon) {
            sample(&world, &events[seen..]);
        }
    }
    let output = RunOutput {
        structure: name,
        objects: scene.objects.len(),
        horizon: scene.horizon,
        events,
        stats: world.stats().clone(),
        structure_stats: world.structure_counters(),
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    output.finish(result, world.now())
}

impl RunOutput {
    /// The output of a run that ended at `now` with `result`: stopped runs keep it as partial.
    fn finish(self, result: Result<(), WorldError>, now: f64) -> Result<RunOutput, RunError> {
        match result {
            Ok(()) => Ok(self),
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
            "structure_stats": self.structure_stats.iter().map(|&(k, v)| (k.to_string(), serde_json::json!(v))).collect::<serde_json::Map<_, _>>(),
            "wall_seconds": self.wall_seconds,
        });
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

/// Writes `text` to `path` whole or not at all (through a temporary file and a rename).
pub fn write_whole(path: &std::path::Path, text: &str) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)
}
