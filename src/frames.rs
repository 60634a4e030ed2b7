//! Frames: snapshots of a run at even times over its horizon, rendered to PNG
//! (`out/<scene>/frame_0000.png`, ...).
//!
//! Objects in contact are highlighted (in red): pairs touching at the frame's time, and
//! objects that began a contact since the previous frame (under `elastic`, contacts are
//! instants). Optional overlays show what the structure is doing ([`Overlay`]).

use glam::Vec3 as F3;
use kinetic_collide::Structure;
use kinetic_collide::run::{RunError, RunOutput, Stream, holding_events, run_scene_streamed};
use kinetic_collide::scene::{Scene, ShapeSpec};
use kinetic_collide::{World, WorldKind};
use kinetic_render::{AdapterChoice, Camera, HullMesh, Instance, RenderError, Renderer, Snapshot};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What to draw over the objects.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Overlay {
    /// Nothing.
    #[default]
    None,
    /// A line between the centres of every candidate pair (any structure).
    Candidates,
    /// The structure's boxes: threshold boxes of the rolling tree (flat on the plane), the
    /// boxes of the sweep and of guards.
    Boxes,
}

impl Overlay {
    /// `none`, `candidates` or `boxes`.
    pub fn parse(name: &str) -> Result<Overlay, RunError> {
        match name {
            "none" => Ok(Overlay::None),
            "candidates" => Ok(Overlay::Candidates),
            "boxes" => Ok(Overlay::Boxes),
            _ => Err(RunError::Input(format!(
                "--overlay {name:?}: expected none, candidates or boxes"
            ))),
        }
    }
}

/// How many frames, how large, with what overlay.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameSpec {
    /// Frames at even times over `[0, horizon]` (both ends included when 2 or more).
    pub count: usize,
    /// Picture width in pixels.
    pub width: u32,
    /// Picture height in pixels.
    pub height: u32,
    /// What to draw over the objects.
    pub overlay: Overlay,
}

impl Default for FrameSpec {
    /// No frames; 640x480 and no overlay when some are asked for.
    fn default() -> FrameSpec {
        FrameSpec {
            count: 0,
            width: 640,
            height: 480,
            overlay: Overlay::None,
        }
    }
}

impl FrameSpec {
    /// Parses a `WxH` size such as `640x480`.
    pub fn parse_size(text: &str) -> Result<(u32, u32), RunError> {
        let bad = || RunError::Input(format!("--size {text:?}: expected WxH, e.g. 640x480"));
        let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
        let (w, h) = (
            w.parse::<u32>().map_err(|_| bad())?,
            h.parse::<u32>().map_err(|_| bad())?,
        );
        if w == 0 || h == 0 || w > 8192 || h > 8192 {
            return Err(RunError::Input(format!(
                "--size {text}: each side must be 1 to 8192 pixels"
            )));
        }
        Ok((w, h))
    }
}

/// The frame times: `count` even times over `[0, horizon]`.
pub fn frame_times(horizon: f64, count: usize) -> Vec<f64> {
    match count {
        0 => Vec::new(),
        1 => vec![0.0],
        n => (0..n)
            .map(|k| horizon * k as f64 / (n - 1) as f64)
            .collect(),
    }
}

/// Soft colours for objects at rest from contact (linear RGB), by object id.
pub const PALETTE: [[f32; 4]; 6] = [
    [0.30, 0.45, 0.70, 1.0],
    [0.55, 0.60, 0.35, 1.0],
    [0.35, 0.60, 0.55, 1.0],
    [0.55, 0.45, 0.70, 1.0],
    [0.70, 0.60, 0.40, 1.0],
    [0.40, 0.50, 0.55, 1.0],
];
/// Objects in contact.
pub const CONTACT: [f32; 4] = [0.90, 0.06, 0.02, 1.0];
/// The plane, and fixed ground.
pub const PLANE: [f32; 4] = [0.50, 0.50, 0.46, 1.0];
const CANDIDATE_LINE: [f32; 4] = [0.05, 0.05, 0.05, 1.0];
const BOX_LINE: [f32; 4] = [0.02, 0.10, 0.45, 1.0];

/// Turns a world into snapshots: knows each object's mesh.
#[derive(Clone, Debug)]
pub struct Painter {
    kind: WorldKind,
    overlay: Overlay,
    hulls: Arc<Vec<HullMesh>>,
    /// Per object: its cuboid half extents or hull mesh index (balls: neither).
    meshes: Vec<ObjectMesh>,
}

#[derive(Clone, Copy, Debug)]
enum ObjectMesh {
    Ball(f32),
    Cuboid(F3),
    Hull(u32),
}

impl Painter {
    /// A painter for the objects of `scene`.
    pub fn new(scene: &Scene, overlay: Overlay) -> Painter {
        let mut hulls = Vec::new();
        let meshes = scene
            .objects
            .iter()
            .map(|o| match &o.shape {
                ShapeSpec::Ball { radius } => ObjectMesh::Ball(*radius as f32),
                ShapeSpec::Cuboid { half_extents } => ObjectMesh::Cuboid(half_extents.as_vec3()),
                ShapeSpec::ConvexHull { points } => {
                    let (points, triangles) =
                        kinetic_collide::parry::transformation::convex_hull(points);
                    hulls.push(HullMesh {
                        points: points.iter().map(|p| p.as_vec3()).collect(),
                        triangles,
                    });
                    ObjectMesh::Hull(hulls.len() as u32 - 1)
                }
            })
            .collect();
        Painter {
            kind: scene.world,
            overlay,
            hulls: Arc::new(hulls),
            meshes,
        }
    }

    /// The world now, with the objects in `contact` highlighted.
    pub fn snapshot(&self, world: &World, contact: &[bool]) -> Snapshot {
        let mut s = Snapshot::new(F3::Z);
        s.hulls = self.hulls.clone();
        let now = world.now();
        let centre = |id: usize| -> Option<F3> {
            let body = world.bodies().get(id)?.as_ref()?;
            let p = body.plan.position_at(now).as_vec3();
            Some(match (self.kind, self.meshes.get(id)) {
                // A rolling ball's plan follows its tangency point; its centre is r above.
                (WorldKind::Plane, Some(ObjectMesh::Ball(r))) => p + F3::Z * *r,
                _ => p,
            })
        };
        for (id, mesh) in self.meshes.iter().enumerate() {
            let (Some(c), Some(Some(body))) = (centre(id), world.bodies().get(id)) else {
                continue;
            };
            let colour = if contact.get(id).copied().unwrap_or(false) {
                CONTACT
            } else {
                PALETTE[id % PALETTE.len()]
            };
            let rotation = body.plan.orientation_at(now).as_quat();
            s.instances.push(match *mesh {
                ObjectMesh::Ball(r) => Instance::ball(c, r, colour),
                ObjectMesh::Cuboid(h) => Instance::cuboid(c, rotation, h, colour),
                ObjectMesh::Hull(i) => Instance::hull(i, c, rotation, colour),
            });
        }
        match self.overlay {
            Overlay::None => {}
            Overlay::Candidates => {
                for (a, b) in world.candidate_pair_list() {
                    if let (Some(a), Some(b)) = (centre(a.0 as usize), centre(b.0 as usize)) {
                        s.lines.push(kinetic_render::Line {
                            a,
                            b,
                            colour: CANDIDATE_LINE,
                        });
                    }
                }
            }
            Overlay::Boxes => {
                // Flat boxes (the rolling tree's) sit just above the plane.
                for (lo, hi) in world.structure_boxes() {
                    let (mut lo, mut hi) = (lo.as_vec3(), hi.as_vec3());
                    if self.kind == WorldKind::Plane {
                        let lift = 1e-3 * (hi - lo).max_element();
                        lo.z += lift;
                        hi.z += lift;
                    }
                    s.wire_box(lo, hi, BOX_LINE);
                }
            }
        }
        s
    }
}

/// A square plane patch under every object of every snapshot (plane worlds).
fn add_plane(snapshots: &mut [Snapshot]) {
    let bounds = snapshots
        .iter()
        .filter_map(Snapshot::bounds)
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
    let Some((lo, hi)) = bounds else { return };
    let centre = F3::new((lo.x + hi.x) * 0.5, (lo.y + hi.y) * 0.5, 0.0);
    let half = ((hi.x - lo.x).max(hi.y - lo.y) * 0.5 * 1.08).max(1e-3);
    for s in snapshots {
        s.instances
            .insert(0, Instance::plane(centre, F3::Z, half, PLANE));
    }
}

/// Runs `scene` to its horizon and takes a snapshot at each frame time. The run's output,
/// its events included, is exactly what [`kinetic_collide::run::run_scene`] gives.
pub fn run_with_snapshots(
    scene: &Scene,
    structure: Option<Structure>,
    spec: &FrameSpec,
) -> Result<(RunOutput, Vec<Snapshot>), RunError> {
    holding_events(|stream| run_with_snapshots_streamed(scene, structure, spec, stream))
}

/// [`run_with_snapshots`], handing the events to `stream` as they happen instead of holding
/// them.
pub fn run_with_snapshots_streamed(
    scene: &Scene,
    structure: Option<Structure>,
    spec: &FrameSpec,
    stream: &mut Stream<'_>,
) -> Result<(RunOutput, Vec<Snapshot>), RunError> {
    let painter = Painter::new(scene, spec.overlay);
    let mut snapshots = Vec::with_capacity(spec.count);
    let times = frame_times(scene.horizon, spec.count);
    let mut sample = |world: &kinetic_collide::World, begun: &[bool]| {
        let mut contact = begun.to_vec();
        contact.resize(world.bodies().len(), false);
        for (a, b) in world.touching_pairs() {
            for id in [a.0, b.0] {
                if let Some(c) = contact.get_mut(id as usize) {
                    *c = true;
                }
            }
        }
        snapshots.push(painter.snapshot(world, &contact));
    };
    let output = run_scene_streamed(scene, structure, &times, &mut sample, stream)?;
    if scene.world == WorldKind::Plane {
        add_plane(&mut snapshots);
    }
    Ok((output, snapshots))
}

/// Writes a run's scene, event log and statistics to `dir/{scene.json, events.jsonl,
/// stats.json}` (each whole or not at all); an error names the file.
pub fn write_run(dir: &Path, scene: &Scene, output: &RunOutput) -> Result<(), String> {
    for (name, text) in [
        ("scene.json", scene.to_json()),
        ("events.jsonl", output.event_log()),
        ("stats.json", output.stats_json()),
    ] {
        let path = dir.join(name);
        crate::output::write_whole(&path, &text)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    Ok(())
}

/// Renders `snapshots` (one camera framing them all) to `dir/frame_0000.png`, ..., with a
/// progress bar on a terminal. Returns the files written.
pub fn render_series(
    snapshots: &[Snapshot],
    width: u32,
    height: u32,
    dir: &Path,
) -> Result<Vec<PathBuf>, RenderError> {
    let camera = Camera::framing_all(snapshots, width as f32 / height as f32);
    render_series_from(snapshots, &camera, width, height, dir)
}

/// [`render_series`] from a given camera.
pub fn render_series_from(
    snapshots: &[Snapshot],
    camera: &Camera,
    width: u32,
    height: u32,
    dir: &Path,
) -> Result<Vec<PathBuf>, RenderError> {
    let mut renderer = Renderer::new(width, height, AdapterChoice::from_env())?;
    let bar = indicatif::ProgressBar::new(snapshots.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("frames {bar:40} {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut written = Vec::with_capacity(snapshots.len());
    for (k, s) in snapshots.iter().enumerate() {
        let path = dir.join(format!("frame_{k:04}.png"));
        renderer.render(s, camera)?.save_png(&path)?;
        written.push(path);
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(written)
}
