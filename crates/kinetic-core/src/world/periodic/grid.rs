//! The cell grid of list centres that neighbour lists are made from.
//!
//! Each cell keeps its first few centres in place, in one flat array, so that the cells
//! around a sphere are read in nine short runs (three neighbouring cells along x sit side by
//! side) rather than through 27 separate allocations; a cell's further centres go to its
//! spill, which ordinary fluids rarely use.

use crate::math::{Real, Vec3, round_near};
use crate::prefetch::prefetch;
use rustc_hash::FxHashMap;

/// A list centre as the grid files it: where, as a fraction of the box along each axis
/// (wrapped into it, in single precision), and which sphere. Four to a cache line.
#[derive(Clone, Copy, Debug)]
#[repr(align(16))]
struct Filed {
    at: [f32; 3],
    id: u32,
}

/// A uniform grid over one period of the box, each cell holding the list centres that lie in
/// it. Centres are kept in single precision: a pair is listed when its centres are within
/// its reach plus a margin that covers the rounding (a hair early, never late).
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
    /// Each sphere's radius, rounded up to single precision; the first filed, and whether
    /// any other differs (when none does, a search takes one reach for every centre).
    radius: Vec<f32>,
    first_radius: f32,
    radii_differ: bool,
    /// What rounding the centres may add to a distance.
    margin: Real,
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
        let empty = Filed {
            at: [0.0; 3],
            id: u32::MAX,
        };
        CentreGrid {
            n,
            places,
            filed: vec![empty; cells * places],
            count: vec![0; cells],
            spill: FxHashMap::default(),
            cell_of: vec![u32::MAX; spheres],
            radius: vec![0.0; spheres],
            first_radius: 0.0,
            radii_differ: false,
            // A stored fraction is within 2^-25 of the centre's: a distance, 2^-25 times the
            // box's diagonal; this is eight times that.
            margin: side.length() * (2.0 as Real).powi(-22),
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

    /// Where `p` lies as a fraction of the box, wrapped into it.
    #[inline]
    fn fraction(&self, p: Vec3) -> [Real; 3] {
        let x = (p - self.min) * self.inv_side;
        let x = x - x.floor();
        [x.x, x.y, x.z]
    }

    /// Files sphere `id`'s list centre `centre`; its radius is `radius`.
    pub(super) fn insert(&mut self, id: u32, centre: Vec3, radius: Real) {
        let mut r = radius as f32;
        if Real::from(r) < radius {
            r = r.next_up();
        }
        self.radius[id as usize] = r;
        if self.first_radius == 0.0 {
            self.first_radius = r;
        } else if r != self.first_radius {
            self.radii_differ = true;
        }
        let x = self.fraction(centre);
        let f = Filed {
            at: x.map(|x| x as f32),
            id,
        };
        let cell = self.index(self.cell(centre));
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

    /// Writes to `found` the spheres whose centres, filed in the 27 cells around that of
    /// `centre`, are within `factor` times the sum of their radius and `radius` (nearest
    /// image, plus the rounding margin). The cells' centres are asked for first, so that they
    /// are fetched together, and tested without a branch on the outcome.
    #[inline]
    pub(super) fn near(&self, centre: Vec3, radius: Real, factor: Real, found: &mut Vec<u32>) {
        found.clear();
        let runs = self.runs(self.cell(centre));
        let me = self.fraction(centre);
        let mut total = 0;
        for run in &runs {
            for &cell in run {
                let at = cell as usize * self.places;
                let k = self.count[cell as usize] as usize;
                total += k;
                // Four centres a line.
                for j in (0..k.min(self.places)).step_by(4) {
                    prefetch(&self.filed[at + j]);
                }
            }
        }
        found.resize(total, 0);
        if self.radii_differ {
            self.test_runs(&runs, me, found, |f| {
                let reach =
                    (radius + Real::from(self.radius[f.id as usize])) * factor + self.margin;
                reach * reach
            });
        } else {
            let reach = (radius + Real::from(self.first_radius)) * factor + self.margin;
            self.test_runs(&runs, me, found, |_| reach * reach);
        }
    }

    /// Tests the centres filed in the cells of `runs` against the centre at `me` (a
    /// fraction of the box), keeping in `found` those closer than the square root of
    /// `reach2(centre)`.
    #[inline(always)]
    fn test_runs(
        &self,
        runs: &[[u32; 3]; 9],
        me: [Real; 3],
        found: &mut Vec<u32>,
        reach2: impl Fn(&Filed) -> Real,
    ) {
        let side = self.side;
        let mut len = 0;
        let mut test = |f: &Filed| {
            found[len] = f.id;
            let mut d2 = 0.0;
            for k in 0..3 {
                let x = me[k] - Real::from(f.at[k]);
                let x = (x - round_near(x)) * side[k];
                d2 += x * x;
            }
            len += usize::from(d2 < reach2(f));
        };
        for run in runs {
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
    /// and removed: the grid stays whole, and finds every centre within reach and none
    /// beyond reach and margin, with radii that differ and with one radius for all.
    #[test]
    fn crowded_cells_spill_and_near_finds_every_centre_within_reach() {
        search_crowded_cells(|id| 0.2 + 0.01 * (id % 10) as Real, true);
        search_crowded_cells(|_| 0.25, false);
    }

    fn search_crowded_cells(radius: impl Fn(u32) -> Real, differ: bool) {
        let side = Vec3::new(10.0, 9.0, 11.0);
        let n = 300;
        let mut grid = CentreGrid::new(n, Vec3::splat(-1.0), side, 2.0);
        let mut state = 7u64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as Real / (1u64 << 53) as Real
        };
        let mut centres = Vec::new();
        for id in 0..n as u32 {
            // A third in one corner cell, the rest anywhere (a few outside the box).
            let scale = if id % 3 == 0 { 1.5 } else { 11.0 };
            let c = Vec3::new(rand(), rand(), rand()) * scale - 1.0;
            centres.push(c);
            grid.insert(id, c, radius(id));
        }
        grid.validate().unwrap();
        assert!(!grid.spill.is_empty());
        assert_eq!(grid.radii_differ, differ);
        let distance = |a: Vec3, b: Vec3| {
            let d = a - b;
            (d - (d / side).round() * side).length()
        };
        let mut found = Vec::new();
        for round in 0..3 {
            for id in (round..n as u32).step_by(3) {
                grid.remove(id);
                let c = Vec3::new(rand(), rand(), rand()) * 10.0;
                centres[id as usize] = c;
                grid.insert(id, c, radius(id));
                grid.validate().unwrap();
            }
            for id in (0..n as u32).step_by(7) {
                grid.near(centres[id as usize], radius(id), 2.0, &mut found);
                for k in 0..n as u32 {
                    let d = distance(centres[id as usize], centres[k as usize]);
                    let reach = (radius(id) + radius(k)) * 2.0;
                    if d < reach {
                        assert!(found.contains(&k), "round {round}: {id} misses {k}");
                    }
                    if d > reach + grid.margin {
                        assert!(!found.contains(&k), "round {round}: {id} finds {k}");
                    }
                }
            }
        }
    }
}
