//! The guard grid of Lemma 7: where an object's guards are.

use kinetic_core::Real;

/// The guard grid of Lemma 7 for fatness `rho`: `m` planes per axis across the cube of half
/// side `(rho + 1) r`, evenly spaced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardGrid {
    /// The fatness the grid guards against.
    pub rho: Real,
    /// Grid planes per axis (guards per object: `m^3`).
    pub m: u32,
}

impl GuardGrid {
    /// The grid for objects at most `rho`-fat.
    pub fn new(rho: Real) -> GuardGrid {
        let rho = rho.max(1.0);
        // Cells of side at most 2 r / (sqrt 3 (rho + 1)) across a side of 2 (rho + 1) r.
        let cells = (3f64.sqrt() * (rho + 1.0) * (rho + 1.0)).ceil();
        GuardGrid {
            rho,
            m: cells as u32 + 1,
        }
    }

    /// The offset of plane `i` from the centre, for inner radius `r`.
    pub fn offset(&self, r: Real, i: u32) -> Real {
        let half = (self.rho + 1.0) * r;
        -half + 2.0 * half * Real::from(i) / Real::from(self.m - 1)
    }

    /// The guards of an object with centre `c` and inner radius `r`.
    pub fn guards(&self, c: glam::DVec3, r: Real) -> impl Iterator<Item = glam::DVec3> + '_ {
        let m = self.m;
        (0..m * m * m).map(move |k| {
            let (i, j, l) = (k % m, (k / m) % m, k / (m * m));
            c + glam::DVec3::new(self.offset(r, i), self.offset(r, j), self.offset(r, l))
        })
    }
}
