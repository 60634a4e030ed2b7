//! The cones of Section 3.2: the space around a guard cut into narrow cones, each with a
//! representative edge, so that among the objects whose centres lie in one cone and whose
//! boxes hold the guard, only the closest along that edge can contain the guard (Lemma 9).
//!
//! Every face of the cube [-1, 1]^3 is cut into `cells x cells` squares, each square into two
//! triangles by its diagonal, and each triangle spans a cone from the origin. The
//! representative edge of a cone is the ray through its triangle's right-angle corner.
//!
//! The proof of Lemma 9 needs every ray of a cone within `arctan(1 / (2 sqrt 3 rho))` of the
//! representative edge. Lemma 8's cell side `1 / (2 sqrt 6 rho)` (on the unit cube) gives
//! cones about twice that wide near the face centres, so [`ConeSet::new`] refines the grid
//! until the widest angle from any representative edge is within the bound: 7 cells per face
//! side for rho = 1 (588 cones), 21 for rho = 3.

use kinetic_core::{Real, Vec3};

/// One cone from the origin: three unit rays through its triangle's corners, the inward unit
/// normals of its three facet planes (all through the origin) and its representative edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Unit rays through the corners; `rays[0]` is the representative edge.
    pub rays: [Vec3; 3],
    /// Inward unit normals: `d` is in the (closed) cone when `normals[k] . d >= 0` for all k.
    pub normals: [Vec3; 3],
}

impl Cone {
    /// The representative edge (a unit vector).
    pub fn edge(&self) -> Vec3 {
        self.rays[0]
    }

    /// Whether `d` lies in the closed cone.
    pub fn contains(&self, d: Vec3) -> bool {
        self.normals.iter().all(|n| n.dot(d) >= 0.0)
    }

    /// The widest angle between the representative edge and a ray of the cone.
    pub fn width(&self) -> Real {
        self.rays[1..]
            .iter()
            .map(|r| self.rays[0].angle_between(*r))
            .fold(0.0, Real::max)
    }
}

/// The standard cones for one fatness; every guard's cones are translates of these.
#[derive(Clone, Debug)]
pub struct ConeSet {
    rho: Real,
    cells: u32,
    cones: Vec<Cone>,
}

impl ConeSet {
    /// The cones for objects at most `rho`-fat: the coarsest face grid whose cones are all
    /// within `arctan(1 / (2 sqrt 3 rho))` of their representative edges (with a relative
    /// margin of 1e-6).
    pub fn new(rho: Real) -> ConeSet {
        let rho = rho.max(1.0);
        let limit = ((1.0 - 1e-6) / (2.0 * 3f64.sqrt() * rho)).atan();
        let mut cells = (2.0 * 6f64.sqrt() * rho).ceil() as u32;
        loop {
            let set = ConeSet::with_cells(rho, cells);
            if set.cones.iter().all(|c| c.width() <= limit) {
                return set;
            }
            cells += 1;
        }
    }

    fn with_cells(rho: Real, cells: u32) -> ConeSet {
        let n = cells as usize;
        let mut cones = Vec::with_capacity(12 * n * n);
        for face in 0..6 {
            for iu in 0..cells {
                for iw in 0..cells {
                    for t in 0..2 {
                        cones.push(Self::build(face, cells, iu, iw, t));
                    }
                }
            }
        }
        ConeSet { rho, cells, cones }
    }

    /// The cone of triangle `t` of cell (`iu`, `iw`) on `face`.
    fn build(face: u32, cells: u32, iu: u32, iw: u32, t: u32) -> Cone {
        let (a, b, c, s) = Self::face_axes(face);
        let grid = |i: u32| -1.0 + 2.0 * Real::from(i) / Real::from(cells);
        let (u0, u1, w0, w1) = (grid(iu), grid(iu + 1), grid(iw), grid(iw + 1));
        let point = |u: Real, w: Real| {
            let mut p = Vec3::ZERO;
            p[a] = s;
            p[b] = u;
            p[c] = w;
            p.normalize()
        };
        // Triangle 0 lies below the diagonal (u0, w0)-(u1, w1), triangle 1 above it; the
        // right-angle corner comes first.
        let rays = if t == 0 {
            [point(u1, w0), point(u0, w0), point(u1, w1)]
        } else {
            [point(u0, w1), point(u1, w1), point(u0, w0)]
        };
        let normals = std::array::from_fn(|k| {
            let (p, q, r) = (rays[k], rays[(k + 1) % 3], rays[(k + 2) % 3]);
            let n = p.cross(q).normalize();
            if n.dot(r) < 0.0 { -n } else { n }
        });
        Cone { rays, normals }
    }

    /// The face's main axis, its two other axes in increasing order, and its side (+1/-1).
    fn face_axes(face: u32) -> (usize, usize, usize, Real) {
        let a = (face / 2) as usize;
        let (b, c) = match a {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        (a, b, c, if face.is_multiple_of(2) { 1.0 } else { -1.0 })
    }

    /// The fatness the cones are built for.
    pub fn rho(&self) -> Real {
        self.rho
    }

    /// Grid cells per face side.
    pub fn cells(&self) -> u32 {
        self.cells
    }

    /// Number of cones.
    pub fn len(&self) -> usize {
        self.cones.len()
    }

    /// Whether there are no cones (never).
    pub fn is_empty(&self) -> bool {
        self.cones.is_empty()
    }

    /// Cone `i`.
    pub fn cone(&self, i: u32) -> &Cone {
        &self.cones[i as usize]
    }

    /// All cones.
    pub fn cones(&self) -> &[Cone] {
        &self.cones
    }

    /// A cone holding direction `d` (one of them when `d` is on a facet; cone 0 for zero).
    pub fn locate(&self, d: Vec3) -> u32 {
        let abs = d.abs();
        let a = if abs.x >= abs.y && abs.x >= abs.z {
            0
        } else if abs.y >= abs.z {
            1
        } else {
            2
        };
        if abs[a] == 0.0 || !abs[a].is_finite() {
            return 0;
        }
        let face = 2 * a as u32 + u32::from(d[a] < 0.0);
        let (_, b, c, _) = Self::face_axes(face);
        let n = Real::from(self.cells);
        let cell = |x: Real| {
            let f = ((x / abs[a]).clamp(-1.0, 1.0) + 1.0) * 0.5 * n;
            let i = (f.floor() as u32).min(self.cells - 1);
            (i, f - Real::from(i))
        };
        let ((iu, fu), (iw, fw)) = (cell(d[b]), cell(d[c]));
        let t = u32::from(fw > fu);
        ((face * self.cells + iu) * self.cells + iw) * 2 + t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cones_tile_every_direction_and_are_narrow_enough() {
        for rho in [1.0, 1.7, 3.0] {
            let set = ConeSet::new(rho);
            let limit = (1.0 / (2.0 * 3f64.sqrt() * rho)).atan();
            assert!(set.cones().iter().all(|c| c.width() <= limit));
            assert_eq!(set.len(), 12 * (set.cells() as usize).pow(2));
            let mut seed = 0x2545_f491_4f6c_dd1du64;
            let mut next = || {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            for _ in 0..5000 {
                let d = Vec3::new(next(), next(), next());
                let i = set.locate(d);
                assert!(
                    set.cone(i)
                        .normals
                        .iter()
                        .all(|n| n.dot(d) >= -1e-12 * d.length()),
                    "{d} not in cone {i}"
                );
            }
        }
        assert_eq!(ConeSet::new(1.0).cells(), 7);
    }
}
