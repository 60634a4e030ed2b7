//! What to draw: a snapshot of a scene at one moment, in `f32` world coordinates.

use glam::{Mat4, Quat, Vec3};
use std::sync::Arc;

/// The mesh an instance draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MeshKind {
    /// The unit ball (radius 1), scaled by the instance's transform.
    Ball,
    /// The cube `[-1, 1]^3`, scaled to the half extents by the transform.
    Cuboid,
    /// The square `[-1, 1]^2` at z = 0, facing +z: a plane patch.
    Quad,
    /// The `i`-th mesh of [`Snapshot::hulls`], in its own frame.
    Hull(u32),
}

/// One object to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Which mesh.
    pub mesh: MeshKind,
    /// Mesh frame to world (translation, rotation, scale).
    pub transform: Mat4,
    /// Linear RGBA.
    pub colour: [f32; 4],
}

impl Instance {
    /// A ball of `radius` at `centre`.
    pub fn ball(centre: Vec3, radius: f32, colour: [f32; 4]) -> Instance {
        Instance {
            mesh: MeshKind::Ball,
            transform: Mat4::from_scale_rotation_translation(
                Vec3::splat(radius),
                Quat::IDENTITY,
                centre,
            ),
            colour,
        }
    }

    /// A cuboid of `half_extents` turned by `rotation` about its centre.
    pub fn cuboid(centre: Vec3, rotation: Quat, half_extents: Vec3, colour: [f32; 4]) -> Instance {
        Instance {
            mesh: MeshKind::Cuboid,
            transform: Mat4::from_scale_rotation_translation(half_extents, rotation, centre),
            colour,
        }
    }

    /// Hull mesh `index` placed at `origin` turned by `rotation`.
    pub fn hull(index: u32, origin: Vec3, rotation: Quat, colour: [f32; 4]) -> Instance {
        Instance {
            mesh: MeshKind::Hull(index),
            transform: Mat4::from_rotation_translation(rotation, origin),
            colour,
        }
    }

    /// A square plane patch of half side `half` centred at `centre`, facing `normal`.
    pub fn plane(centre: Vec3, normal: Vec3, half: f32, colour: [f32; 4]) -> Instance {
        let rotation = Quat::from_rotation_arc(Vec3::Z, normal.normalize());
        Instance {
            mesh: MeshKind::Quad,
            transform: Mat4::from_scale_rotation_translation(
                Vec3::new(half, half, 1.0),
                rotation,
                centre,
            ),
            colour,
        }
    }

    /// Points that outline the instance in world space: the corners of its mesh's box, or
    /// for a ball 14 points of its surface (axes and diagonals), close to its outline from
    /// any side.
    pub fn outline(&self, hulls: &[HullMesh]) -> Vec<Vec3> {
        let (min, max) = match self.mesh {
            MeshKind::Ball => {
                let (scale, _, centre) = self.transform.to_scale_rotation_translation();
                let r = scale.abs().max_element();
                let diagonal = box_corners(Vec3::splat(-1.0), Vec3::ONE).map(|d| d.normalize());
                let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
                return diagonal
                    .iter()
                    .chain(&axes)
                    .map(|d| centre + *d * r)
                    .collect();
            }
            MeshKind::Cuboid => (Vec3::splat(-1.0), Vec3::ONE),
            MeshKind::Quad => (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
            MeshKind::Hull(i) => hulls.get(i as usize).map_or((Vec3::ZERO, Vec3::ZERO), |h| {
                h.points
                    .iter()
                    .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                        (lo.min(p), hi.max(p))
                    })
            }),
        };
        box_corners(min, max)
            .iter()
            .map(|&p| self.transform.transform_point3(p))
            .collect()
    }
}

/// The 8 corners of the box `[min, max]`.
pub(crate) fn box_corners(min: Vec3, max: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    })
}

/// A convex polyhedron's surface: its points and outward triangles (counter-clockwise seen
/// from outside), in the frame its instances are placed by.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HullMesh {
    /// The vertices.
    pub points: Vec<Vec3>,
    /// Triangles as indices into `points`.
    pub triangles: Vec<[u32; 3]>,
}

/// A line segment drawn over the scene (overlays: boxes, candidate pairs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// One end.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// Linear RGBA.
    pub colour: [f32; 4],
}

/// A scene at one moment.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    /// The objects (and the plane, as a [`MeshKind::Quad`] instance).
    pub instances: Vec<Instance>,
    /// Hull meshes referred to by [`MeshKind::Hull`]; shared between the frames of a series
    /// (the renderer uploads them again only when this `Arc` changes).
    pub hulls: Arc<Vec<HullMesh>>,
    /// Overlay lines.
    pub lines: Vec<Line>,
    /// The world's up direction (the camera keeps it up).
    pub up: Vec3,
}

impl Snapshot {
    /// An empty snapshot whose up direction is `up`.
    pub fn new(up: Vec3) -> Snapshot {
        Snapshot {
            up,
            ..Snapshot::default()
        }
    }

    /// Adds the 12 edges of the axis-aligned box `[min, max]`.
    pub fn wire_box(&mut self, min: Vec3, max: Vec3, colour: [f32; 4]) {
        let corner = box_corners(min, max);
        for i in 0..8 {
            for bit in [1, 2, 4] {
                if i & bit == 0 {
                    self.lines.push(Line {
                        a: corner[i],
                        b: corner[i | bit],
                        colour,
                    });
                }
            }
        }
    }

    /// Points that outline everything drawn (instances and lines).
    pub fn points(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.instances
            .iter()
            .flat_map(|i| i.outline(&self.hulls))
            .chain(self.lines.iter().flat_map(|l| [l.a, l.b]))
            .filter(|p| p.is_finite())
    }

    /// The axis-aligned box of everything drawn, or `None` for an empty snapshot.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.points().fold(None, |b, p| match b {
            None => Some((p, p)),
            Some((lo, hi)) => Some((p.min(lo), p.max(hi))),
        })
    }
}
