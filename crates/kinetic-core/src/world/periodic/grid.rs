//! The cell grid of list centres that neighbour lists are made from.
//!
//! Each cell keeps its first few centres in place, in one flat array, so that the cells
//! around a sphere are read in nine short runs (three neighbouring cells along x sit side by
//! side) rather than through 27 separate allocations; a cell's further centres go to its
//! spill, which ordinary fluids rarely use.

use super::Period;
use crate::math::{Real, Vec3};
use crate::prefetch::prefetch;
use rustc_hash::FxHashMap;

/// A list centre as the grid files it: where, the sphere's radius rounded up to `f32` (a
/// pair is listed a hair early, never late), which sphere. Two to a cache line.
#[derive(Clone, Copy, Debug)]
#[repr(align(32))]
pub(super) struct Filed {
    pub(super) centre: Vec3,
    radius: f32,
    pub(super) id: u32,
}

impl Filed {
    pub(super) fn new(centre: Vec3, radius: Real, id: u32) -> Filed {
        let mut r = radius as f32;
        if Real::from(r) < radius {
            r = r.next_up();
        }
        Filed {
            centre,
            radius: r,
            id,
        }
    }

    /// Whether the centres of `self` and `other` are within `factor` times their sum of
    /// radii (nearest image).
    #[inline]
    pub(super) fn near(&self, period: &Period, factor: Real, other: &Filed) -> bool {
        let (d, _) = period.apart(self.centre - other.centre);
        let reach = (Real::from(self.radius) + Real::from(other.radius)) * factor;
        d.length_squared() < reach * reach
    }
}

/// A uniform grid over one period of the box, each cell holding the list centres that lie in
/// it (with the radii, so listing reads one place per candidate).
#[derive(Clone, Debug)]
pub(super) struct CentreGrid {
    n: [u32; 3],
    /// Centres held in place per cell: cell `c`'s are at `c * places ..`.
    places: usize,
    filed: Vec<Filed>,
    /// Centres per cell, those in its spill included.
    count: Vec<u32>,
    /// Each crowded cell's centres beyond its places.
    spill: FxHashMap<u32, Vec<Filed>>,
    cell_of: Vec<u32>,
    /// Cells per unit length along each axis.
    scale: Vec3,
    min: Vec3,
    side: Vec3,
    inv_side: Vec3,
}

impl CentreGrid {
    /// A grid for `spheres` over a box at `min` of `side`, with cells at least `reach` wide
    /// (at least 3 per axis: the caller checks), no more than about 2 per sphere.
    pub(super) fn new(spheres: usize, min: Vec3, side: Vec3, reach: Real) -> CentreGrid {
        let mut n = [0u32; 3];
        for k in 0..3 {
            n[k] = ((side[k] / (reach * (1.0 + 1e-6))).floor().min(1e6) as u32).max(3);
        }
        while (n[0] as u64 * n[1] as u64 * n[2] as u64) > 2 * spheres as u64 + 27
            && n.iter().all(|&c| c > 3)
        {
            for c in &mut n {
                *c = (*c * 9 / 10).max(3);
            }
        }
        let cells = n[0] as usize * n[1] as usize * n[2] as usize;
        // Room for twice the mean, 2 to 8 places: a cell spills rarely.
        let mean = spheres as Real / cells as Real;
        let places = ((2.0 * mean).ceil() as usize).clamp(2, 8);
        let empty = Filed::new(Vec3::ZERO, 0.0, u32::MAX);
        CentreGrid {
            n,
            places,
            filed: vec![empty; cells * places],
            count: vec![0; cells],
            spill: FxHashMap::default(),
            cell_of: vec![u32::MAX; spheres],
            scale: Vec3::new(n[0] as Real, n[1] as Real, n[2] as Real) / side,
            min,
            side,
            inv_side: Vec3::ONE / side,
        }
    }

    pub(super) fn cells(&self) -> usize {
        self.count.len()
    }

    /// The cell of a point, wrapped into the box.
    #[inline]
    pub(super) fn cell(&self, p: Vec3) -> [u32; 3] {
        let p = p - self.min;
        let mut c = [0u32; 3];
        for k in 0..3 {
            let w = p[k] - (p[k] * self.inv_side[k]).floor() * self.side[k];
            let x = (w * self.scale[k]).floor();
            c[k] = if x < 0.0 {
                0
            } else {
                (x as u32).min(self.n[k] - 1)
            };
        }
        c
    }

    #[inline]
    fn index(&self, c: [u32; 3]) -> u32 {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    pub(super) fn insert(&mut self, f: Filed) {
        let cell = self.index(self.cell(f.centre));
        let c = cell as usize;
        let k = self.count[c] as usize;
        if k < self.places {
            self.filed[c * self.places + k] = f;
        } else {
            self.spill.entry(cell).or_default().push(f);
        }
        self.count[c] += 1;
        self.cell_of[f.id as usize] = cell;
    }

    pub(super) fn remove(&mut self, id: u32) {
        let cell = std::mem::replace(&mut self.cell_of[id as usize], u32::MAX);
        let c = cell as usize;
        let k = self.count[c] as usize;
        let placed = &mut self.filed[c * self.places..c * self.places + k.min(self.places)];
        if let Some(at) = placed.iter().position(|f| f.id == id) {
            // The cell's last centre takes the hole: from the spill if it has one.
            let last = if k > self.places {
                let spill = self.spill.get_mut(&cell).expect("a spilt cell");
                let last = spill.pop().expect("a spilt centre");
                if spill.is_empty() {
                    self.spill.remove(&cell);
                }
                last
            } else {
                placed[k - 1]
            };
            placed[at] = last;
        } else if let Some(spill) = self.spill.get_mut(&cell)
            && let Some(at) = spill.iter().position(|f| f.id == id)
        {
            spill.swap_remove(at);
            if spill.is_empty() {
                self.spill.remove(&cell);
            }
        } else {
            return;
        }
        self.count[c] -= 1;
    }

    /// The 27 cells around `c` (with wrap-around) as nine runs of three along x, each a
    /// range of cells `(first, last)` or, where the run wraps, a cell and a range.
    #[inline]
    fn runs(&self, c: [u32; 3]) -> [[u32; 3]; 9] {
        let n = self.n;
        let mut runs = [[0; 3]; 9];
        let mut at = 0;
        for dz in [n[2] - 1, 0, 1] {
            let z = (c[2] + dz) % n[2];
            for dy in [n[1] - 1, 0, 1] {
                let y = (c[1] + dy) % n[1];
                let row = self.index([0, y, z]);
                for (j, dx) in [n[0] - 1, 0, 1].into_iter().enumerate() {
                    runs[at][j] = row + (c[0] + dx) % n[0];
                }
                at += 1;
            }
        }
        runs
    }

    /// Writes to `found` the spheres whose centres, filed in the 27 cells around `me`'s
    /// (with wrap-around), are within `factor` times the sum of radii of `me`'s (nearest
    /// image). The cells' centres are asked for first, so that they are fetched together,
    /// and tested without a branch on the outcome.
    #[inline]
    pub(super) fn near(&self, me: &Filed, period: &Period, factor: Real, found: &mut Vec<u32>) {
        found.clear();
        let runs = self.runs(self.cell(me.centre));
        let mut total = 0;
        for run in &runs {
            for &cell in run {
                let at = cell as usize * self.places;
                let k = self.count[cell as usize] as usize;
                total += k;
                // Two centres a line.
                for j in (0..k.min(self.places)).step_by(2) {
                    prefetch(&self.filed[at + j]);
                }
            }
        }
        found.resize(total, 0);
        let mut len = 0;
        let mut test = |f: &Filed| {
            found[len] = f.id;
            len += usize::from(me.near(period, factor, f));
        };
        for run in &runs {
            for &cell in run {
                let c = cell as usize;
                let k = self.count[c] as usize;
                let at = c * self.places;
                for f in &self.filed[at..at + k.min(self.places)] {
                    test(f);
                }
                if k > self.places {
                    for f in &self.spill[&cell] {
                        test(f);
                    }
                }
            }
        }
        found.truncate(len);
    }

    /// Checks the grid against the centres it should hold (for tests).
    pub(super) fn validate(&self) -> Result<(), String> {
        let mut held = 0;
        for (c, &k) in self.count.iter().enumerate() {
            let spilt = self.spill.get(&(c as u32)).map_or(0, Vec::len);
            if k as usize != (k as usize).min(self.places) + spilt {
                return Err(format!("grid: cell {c} counts {k}, spills {spilt}"));
            }
            let placed =
                &self.filed[c * self.places..c * self.places + (k as usize).min(self.places)];
            let spill = self
                .spill
                .get(&(c as u32))
                .map(Vec::as_slice)
                .unwrap_or(&[]);
            for f in placed.iter().chain(spill) {
                if self.cell_of[f.id as usize] != c as u32 {
                    return Err(format!(
                        "grid: sphere {} filed in cell {c}, not its own",
                        f.id
                    ));
                }
                held += 1;
            }
        }
        let filed = self.cell_of.iter().filter(|&&c| c != u32::MAX).count();
        if held != filed {
            return Err(format!("grid: {held} centres held, {filed} filed"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Centres crowded into a few cells (spilling) and spread over the rest, filed, moved
    /// and removed: the grid stays whole and finds exactly the centres within reach.
    #[test]
    fn crowded_cells_spill_and_near_finds_every_centre_within_reach() {
        let side = Vec3::splat(10.0);
        let period = Period {
            min: Vec3::ZERO,
            side,
            inv_side: Vec3::ONE / side,
            half_side: side * 0.5,
        };
        let n = 300;
        let mut grid = CentreGrid::new(n, Vec3::ZERO, side, 2.0);
        let mut state = 7u64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as Real / (1u64 << 53) as Real
        };
        let mut centres = Vec::new();
        for id in 0..n as u32 {
            // A third in one corner cell, the rest anywhere.
            let scale = if id % 3 == 0 { 1.5 } else { 10.0 };
            let c = Vec3::new(rand(), rand(), rand()) * scale;
            centres.push(c);
            grid.insert(Filed::new(c, 0.3, id));
        }
        grid.validate().unwrap();
        assert!(!grid.spill.is_empty());
        let mut found = Vec::new();
        for round in 0..3 {
            for id in (round..n as u32).step_by(3) {
                grid.remove(id);
                let c = Vec3::new(rand(), rand(), rand()) * 10.0;
                centres[id as usize] = c;
                grid.insert(Filed::new(c, 0.3, id));
                grid.validate().unwrap();
            }
            for id in (0..n as u32).step_by(7) {
                let me = Filed::new(centres[id as usize], 0.3, id);
                grid.near(&me, &period, 2.0, &mut found);
                found.sort_unstable();
                let want: Vec<u32> = (0..n as u32)
                    .filter(|&k| me.near(&period, 2.0, &Filed::new(centres[k as usize], 0.3, k)))
                    .collect();
                assert_eq!(found, want, "round {round}, sphere {id}");
            }
        }
    }
}
