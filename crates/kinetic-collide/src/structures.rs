//! The registry of structures: every structure once, with its command-line name, what it
//! applies to and how it is made, and the default's choice among them for a scene. The
//! command-line tool, `compare`, the library's scene runner and the benches all go through it.

use crate::World;
use crate::run::RunError;
use crate::scene::{Scene, ShapeSpec};
use kinetic_core::{
    BruteForce, CandidateStructure, ElasticCells, FlightPlan, PeriodicBox, Response, Shape, Walls,
    WorldKind,
};
use kinetic_flight::{Choice, ConvexShape, Grid, Guards, LooseGrid, Sweep};
use kinetic_rolling::{ListLayout, RollingTree};

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
    /// Elastic balls in a periodic box, with neighbour lists and one scheduled event per ball
    /// (bulk hard-sphere fluids); the only structure for periodic scenes.
    Periodic,
    /// One certificate per pair: the exact reference.
    BruteForce,
}

impl StructureName {
    /// Every name, as written on the command line.
    pub const ALL: [(&'static str, StructureName); 9] = [
        ("rolling-tree", StructureName::RollingTree),
        ("rolling-global-lists", StructureName::RollingGlobalLists),
        (Choice::Sweep.name(), StructureName::Sweep),
        (Choice::Guards.name(), StructureName::Guards),
        (Choice::Grid.name(), StructureName::Grid),
        (Choice::Loose.name(), StructureName::LooseGrid),
        ("cells", StructureName::Cells),
        ("periodic", StructureName::Periodic),
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
        if scene.periodic.is_some() {
            return self == StructureName::Periodic;
        }
        match self {
            StructureName::Periodic => false,
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

impl From<Choice> for StructureName {
    fn from(c: Choice) -> StructureName {
        match c {
            Choice::Sweep => StructureName::Sweep,
            Choice::Guards => StructureName::Guards,
            Choice::Grid => StructureName::Grid,
            Choice::Loose => StructureName::LooseGrid,
        }
    }
}

/// The structure a scene gets when none is named: the one measured fastest for scenes like
/// it on the choice family (`cargo bench --bench choice`, `docs/results/choice.md`), which is
/// not always the one the paper's theorems favour.
///
/// A periodic box gets the periodic structure ([`crate::PeriodicSpheres`]), the only one
/// that wraps. Elastic balls moving linearly inside walls get the cell grid
/// ([`ElasticCells`]), one scheduled event per ball, when it fits their sizes. A scene whose
/// pairs cost the brute force less than a box structure's objects and [`crossings`] cost it
/// ([`kinetic_flight::brute_force_pays`]: a few dozen objects, or a few hundred flying far
/// without bouncing; where the box structure is the grid, its crossings are of its cells,
/// [`kinetic_flight::grid_crossing_share`], and where it is the sweep, the box ends it
/// passes, [`passes`]) gets the brute force. Every other scene gets the flight structure of
/// [`kinetic_flight::for_flights`] for the spread of its sizes (largest over smallest outer
/// radius) and whether its objects barely move: the loose grid, the grid or the sweep. Plane
/// worlds are held by the same box structures (a rolling ball's disc holds its contacts).
/// The paper's other structures (rolling tree, guards) stay selectable by name.
pub fn choose_structure(scene: &Scene) -> StructureName {
    if scene.periodic.is_some() {
        return StructureName::Periodic;
    }
    if cell_balls(scene).is_some() {
        return StructureName::Cells;
    }
    let elastic = scene.response == Response::Elastic;
    let (n, crossings) = (scene.objects.len(), crossings(scene));
    let resting = kinetic_flight::barely_moving(n, crossings);
    let plane = scene.world == WorldKind::Plane;
    let boxes = kinetic_flight::for_flights(scene.size_ratio(), n, resting, plane);
    let cells = match boxes {
        Choice::Grid => crossings * kinetic_flight::grid_crossing_share(radii(scene)),
        Choice::Sweep => kinetic_flight::sweep_crossings(passes(scene)),
        _ => crossings,
    };
    let (contacts, heavy) = (contacts(scene), heavy_pairs(scene));
    if kinetic_flight::brute_force_pays(n, cells, contacts, heavy, elastic) {
        return StructureName::BruteForce;
    }
    boxes.into()
}

/// The outer radii of a scene's objects.
pub fn radii(scene: &Scene) -> impl Iterator<Item = f64> + '_ {
    scene
        .objects
        .iter()
        .map(|o| crate::scene::outer_radius(&o.shape))
}

/// How many times the objects cross their own size over the horizon, summed: each object's
/// travel (speed times horizon, plus half its acceleration times the horizon squared) over
/// its diameter, at most [`FLIGHT_PARTS`] (the grids' least flight). What a box structure
/// pays for in events, where the brute force pays for every pair once.
pub fn crossings(scene: &Scene) -> f64 {
    let h = scene.horizon;
    scene
        .objects
        .iter()
        .map(|o| {
            let travel = o.velocity.length() * h + 0.5 * o.acceleration.length() * h * h;
            let size = 2.0 * crate::scene::outer_radius(&o.shape);
            if size > 0.0 && travel.is_finite() {
                (travel / size).min(FLIGHT_PARTS)
            } else {
                FLIGHT_PARTS
            }
        })
        .sum()
}

/// About how many box ends the objects pass along the axes over the horizon (three in a free
/// world, two on a plane): each object's travel along an axis times the density of box ends
/// there, `2 n` over the extent of the objects' starts grown by their mean diameter. What the
/// sweep pays for in swaps of its sorted lists, whatever the objects' sizes (measured 1.1 to
/// 1.5 swaps a pass on the choice family). Zero where it cannot be told (starts and sizes
/// that leave no extent): the cost model then takes a box structure, which never costs
/// quadratic memory.
pub fn passes(scene: &Scene) -> f64 {
    let n = scene.objects.len();
    if n == 0 {
        return 0.0;
    }
    let h = scene.horizon;
    let mean = radii(scene).sum::<f64>() / n as f64;
    let (lo, hi) = starts_box(scene);
    let extent = (hi - lo) + glam::DVec3::splat(2.0 * mean);
    let axes = if scene.world == WorldKind::Plane {
        2
    } else {
        3
    };
    let density = |k: usize| 2.0 * n as f64 / extent[k];
    let p: f64 = scene
        .objects
        .iter()
        .map(|o| {
            let travel = o.velocity * h + 0.5 * o.acceleration * h * h;
            (0..axes).map(|k| travel[k].abs() * density(k)).sum::<f64>()
        })
        .sum();
    if p.is_finite() { p } else { 0.0 }
}

/// The box of the objects' starts (their positions at t = 0).
fn starts_box(scene: &Scene) -> (glam::DVec3, glam::DVec3) {
    scene.objects.iter().fold(
        (glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY),
        |(lo, hi), o| (lo.min(o.position), hi.max(o.position)),
    )
}

/// About how many contacts the objects make over the horizon: each object's travel through
/// the others as if they stood still, `pi (r_i + r_j)^2` of space swept per unit of travel for
/// each other object `j` (in a plane world the discs' `2 (r_i + r_j)` of area), over the
/// space they share: the walls' box, or else the box of the objects' starts grown by the
/// largest outer radius. For n equal balls filling a share phi of space this is 6 phi
/// contacts per [`crossings`]; what a box structure pays for in new candidate pairs where
/// objects crowd.
pub fn contacts(scene: &Scene) -> f64 {
    let h = scene.horizon;
    let radius = |o: &crate::scene::SceneObject| crate::scene::outer_radius(&o.shape);
    let (lo, hi) = match scene.walls {
        Some(w) => (w.min, w.max),
        None => {
            let r = radii(scene).fold(0.0, f64::max);
            let (lo, hi) = starts_box(scene);
            (lo - glam::DVec3::splat(r), hi + glam::DVec3::splat(r))
        }
    };
    let d = hi - lo;
    let plane = scene.world == WorldKind::Plane;
    let space = if plane { d.x * d.y } else { d.x * d.y * d.z };
    let n = scene.objects.len() as f64;
    let s1: f64 = scene.objects.iter().map(radius).sum();
    let s2: f64 = scene.objects.iter().map(|o| radius(o).powi(2)).sum();
    let swept: f64 = scene
        .objects
        .iter()
        .map(|o| {
            let travel = o.velocity.length() * h + 0.5 * o.acceleration.length() * h * h;
            let r = radius(o);
            let reach = if plane {
                2.0 * (n * r + s1)
            } else {
                std::f64::consts::PI * (n * r * r + 2.0 * r * s1 + s2)
            };
            travel * reach
        })
        .sum();
    let c = swept / space;
    if c.is_finite() && c > 0.0 { c } else { 0.0 }
}

/// Whether some objects are cuboids or hulls, or accelerate: pairs whose certificates cost
/// the brute force about twice a linear ball pair's.
pub fn heavy_pairs(scene: &Scene) -> bool {
    scene
        .objects
        .iter()
        .any(|o| !matches!(o.shape, ShapeSpec::Ball { .. }) || o.acceleration != glam::DVec3::ZERO)
}

/// The walls and balls of a scene that the cell grid holds: elastic, free, walls, balls only,
/// no accelerations, and sizes for which the grid is small.
pub(crate) fn cell_balls(scene: &Scene) -> Option<(Walls, Vec<(f64, FlightPlan)>)> {
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

/// The periodic box and balls of a periodic scene (its objects are elastic balls moving
/// linearly: the scene format checks that).
pub(crate) fn periodic_balls(scene: &Scene) -> Option<(PeriodicBox, Vec<(f64, FlightPlan)>)> {
    let cell = scene.periodic?;
    let balls = scene
        .objects
        .iter()
        .map(|o| match o.shape {
            ShapeSpec::Ball { radius } => Some((radius, o.plan())),
            _ => None,
        })
        .collect::<Option<Vec<_>>>()?;
    Some((cell, balls))
}

/// Whether the cell grid holds the scene (elastic balls moving linearly inside walls, in a
/// free world, with sizes for which the grid is small).
pub fn cells_hold(scene: &Scene) -> bool {
    cell_balls(scene).is_some()
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
        StructureName::Grid => Ok(Box::new(Grid::new().with_least_flight(least_flight(scene)))),
        StructureName::LooseGrid => Ok(Box::new(
            LooseGrid::new().with_least_flight(least_flight(scene)),
        )),
        StructureName::Guards => Ok(Box::new(Guards::new(kinetic_flight::guard_fatness(shapes)))),
        StructureName::Cells | StructureName::Periodic => Err(RunError::Input(format!(
            "--structure {}: runs whole scenes, not inside a world; frames are drawn from a \
             world (use --structure grid)",
            name.as_str()
        ))),
    }
}

/// Parts of the horizon a grid's region covers at least: an object crossing empty space
/// costs the grids at most about this many events over the run, however long the horizon
/// (two balls flying apart for 1e100 time units are done at once).
const FLIGHT_PARTS: f64 = 1000.0;

/// The least flight of the grids' regions for `scene` (see [`FLIGHT_PARTS`]).
fn least_flight(scene: &Scene) -> f64 {
    scene.horizon / FLIGHT_PARTS
}

/// The world of `scene` at t = 0 with the named structure (or the chosen one).
pub fn build_world(
    scene: &Scene,
    structure: Option<StructureName>,
) -> Result<(World, StructureName), RunError> {
    let shapes = shapes_of(scene)?;
    let name = structure.unwrap_or_else(|| choose_structure(scene));
    if scene.periodic.is_some() {
        return Err(RunError::Input(
            "periodic: a periodic scene runs on the periodic structure, not inside a world \
             (frames and the other structures do not wrap)"
                .to_string(),
        ));
    }
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
