//! Meshes as flat vertex lists (three vertices per triangle): the unit ball, the cube, the
//! quad, and convex hulls.

use crate::snapshot::HullMesh;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// A mesh vertex: position and normal in the mesh frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

fn push(out: &mut Vec<Vertex>, p: Vec3, n: Vec3) {
    out.push(Vertex {
        position: p.to_array(),
        normal: n.to_array(),
    });
}

/// The unit ball: an icosahedron subdivided `levels` times, with smooth normals.
pub(crate) fn ball(levels: u32) -> Vec<Vertex> {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let v = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(|p| Vec3::from_array(p).normalize());
    let faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut tris: Vec<[Vec3; 3]> = faces.iter().map(|f| [v[f[0]], v[f[1]], v[f[2]]]).collect();
    for _ in 0..levels {
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    (a + b).normalize(),
                    (b + c).normalize(),
                    (c + a).normalize(),
                );
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    let mut out = Vec::with_capacity(tris.len() * 3);
    for tri in tris {
        for p in tri {
            push(&mut out, p, p);
        }
    }
    out
}

/// The square `[-1, 1]^2` as two counter-clockwise triangles.
const SQUARE: [(f32, f32); 6] = [
    (-1.0, -1.0),
    (1.0, -1.0),
    (1.0, 1.0),
    (-1.0, -1.0),
    (1.0, 1.0),
    (-1.0, 1.0),
];

/// The cube `[-1, 1]^3` with flat faces.
pub(crate) fn cube() -> Vec<Vertex> {
    let mut out = Vec::with_capacity(36);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let (mut u, mut w) = (Vec3::ZERO, Vec3::ZERO);
            u[(axis + 1) % 3] = 1.0;
            w[(axis + 2) % 3] = 1.0;
            // u x w = +n; flip the winding on the negative face.
            let (u, w) = if sign > 0.0 { (u, w) } else { (w, u) };
            let corner = |a: f32, b: f32| n + u * a + w * b;
            for (a, b) in SQUARE {
                push(&mut out, corner(a, b), n);
            }
        }
    }
    out
}

/// The square `[-1, 1]^2` at z = 0, facing +z (and drawn from both sides).
pub(crate) fn quad() -> Vec<Vertex> {
    let mut out = Vec::with_capacity(6);
    for (x, y) in SQUARE {
        push(&mut out, Vec3::new(x, y, 0.0), Vec3::Z);
    }
    out
}

/// A convex hull with flat faces; triangles are turned outward (away from the points' mean)
/// whatever their given winding.
pub(crate) fn hull(mesh: &HullMesh) -> Vec<Vertex> {
    let n = mesh.points.len().max(1) as f32;
    let mean = mesh.points.iter().copied().sum::<Vec3>() / n;
    let mut out = Vec::with_capacity(mesh.triangles.len() * 3);
    for tri in &mesh.triangles {
        let Some([a, b, c]) = tri
            .iter()
            .map(|&i| mesh.points.get(i as usize).copied())
            .collect::<Option<Vec<_>>>()
            .and_then(|v| <[Vec3; 3]>::try_from(v).ok())
        else {
            continue;
        };
        let mut normal = (b - a).cross(c - a);
        let (b, c) = if normal.dot(a - mean) < 0.0 {
            normal = -normal;
            (c, b)
        } else {
            (b, c)
        };
        let normal = normal.normalize_or_zero();
        for p in [a, b, c] {
            push(&mut out, p, normal);
        }
    }
    out
}
