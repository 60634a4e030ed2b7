//! The cell grid of list centres that neighbour lists are made from.
//!
//! Each cell keeps its first centres in place, in blocks of eight: the eight `x`, then the
//! eight `y`, `z` and ids, two cache lines a block, with empty places at NaN. A search tests
//! every place of the 27 cells around a sphere, four at a time in SSE lanes, in single
//! precision, so that no branch depends on how many centres a cell holds. A cell's further
//! centres go to its spill, which ordinary fluids rarely use.

use kinetic_core::elastic::round_near;
use kinetic_core::prefetch;
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;

/// Places in a block.
const LANES: usize = 8;

/// Eight places of a cell: their centres as fractions of the box along each axis (wrapped
/// into it, in single precision), and their spheres. An empty place has NaN coordinates, so
/// that no distance test keeps it.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Block {
    x: [f32; LANES],
    y: [f32; LANES],
    z: [f32; LANES],
    id: [u32; LANES],
}

impl Block {
    const EMPTY: Block = Block {
        x: [f32::NAN; LANES],
        y: [f32::NAN; LANES],
        z: [f32::NAN; LANES],
        id: [u32::MAX; LANES],
    };
}

/// A centre by itself: its fractions of the box and its sphere.
#[derive(Clone, Copy, Debug)]
struct Filed {
    at: [f32; 3],
    id: u32,
}

impl Filed {
    const EMPTY: Filed = Filed {
        at: [f32::NAN; 3],
        id: u32::MAX,
    };
}

/// What a search tests each place against: the searching centre as fractions of the box,
/// the box's sides, and the squared reach, all in single precision.
#[derive(Clone, Copy, Debug)]
struct Probe {
    me: [f32; 3],
    side: [f32; 3],
    reach2: f32,
}

/// A uniform grid over one period of the box (or over the box inside walls), each cell
/// holding the list centres that lie in it. Centres are kept, and distances to them taken, in single precision: a pair is listed
/// when its centres are within its reach plus a margin that covers the rounding (a hair
/// early, never late).
#[derive(Clone, Debug)]
pub(super) struct CentreGrid {
    n: [u32; 3],
    /// Blocks per cell: cell `c`'s places are the blocks `c * blocks ..`.
    blocks: usize,
    placed: Vec<Block>,
    /// Centres per cell, those in its spill included.
    count: Vec<u32>,
    /// Each crowded cell's centres beyond its places.
    spill: FxHashMap<u32, Vec<Filed>>,
    cell_of: Vec<u32>,
    /// Each sphere's radius, rounded up to single precision; the first filed, the largest,
    /// and whether any differs from the first (when none does, a search takes one reach for
    /// every centre).
    radius: Vec<f32>,
    first_radius: f32,
    largest_radius: f32,
    radii_differ: bool,
    /// What rounding may add to a distance.
    margin: Real,
    /// Cells per unit length along each axis.
    scale: Vec3,
    min: Vec3,
    side: Vec3,
    inv_side: Vec3,
    /// Whether space repeats (a periodic box). Inside walls, neighbours beyond the box's
    /// cells are the always empty cell at the end, and fractions are taken of twice the box,
    /// so that no difference of centres near it wraps.
    wrap: bool,
    /// The length fractions are taken of: the box's side, or twice it inside walls.
    span: Vec3,
}

impl CentreGrid {
    /// A grid for `spheres` over a box at `min` of `side`, with cells at least `reach` wide
    /// (in a periodic box, `wrap`, at least 3 per axis: the caller checks), no more than
    /// about 2 per sphere.
    pub(super) fn new(
        spheres: usize,
        min: Vec3,
        side: Vec3,
        reach: Real,
        wrap: bool,
    ) -> CentreGrid {
        let least = if wrap { 3 } else { 1 };
        let mut n = [0u32; 3];
        for k in 0..3 {
            n[k] = ((side[k] / (reach * (1.0 + 1e-6))).floor().min(1e6) as u32).max(least);
        }
        while (n[0] as u64 * n[1] as u64 * n[2] as u64) > 2 * spheres as u64 + 27
            && n.iter().all(|&c| c > least)
        {
            for c in &mut n {
                *c = (*c * 9 / 10).max(least);
            }
        }
        // Inside walls, one more cell that stays empty: the neighbour beyond the box.
        let cells = n[0] as usize * n[1] as usize * n[2] as usize + usize::from(!wrap);
        let span = if wrap { side } else { 2.0 * side };
        // Room for twice the mean, in one to four blocks: a cell spills rarely.
        let mean = spheres as Real / cells as Real;
        let blocks = ((2.0 * mean / LANES as Real).ceil() as usize).clamp(1, 4);
        CentreGrid {
            n,
            blocks,
            placed: vec![Block::EMPTY; cells * blocks],
            count: vec![0; cells],
            spill: FxHashMap::default(),
            cell_of: vec![u32::MAX; spheres],
            radius: vec![0.0; spheres],
            first_radius: 0.0,
            largest_radius: 0.0,
            radii_differ: false,
            // A stored fraction is within 2^-25 of the centre's; the searching centre's as
            // much, their difference as much again, and the products and sums a few parts in
            // 2^24 of the distance: all within 2^-22 of the box's diagonal. This is four
            // times that.
            margin: span.length() * (2.0 as Real).powi(-20),
            scale: Vec3::new(n[0] as Real, n[1] as Real, n[2] as Real) / side,
            min,
            side,
            inv_side: Vec3::ONE / side,
            wrap,
            span,
        }
    }

    pub(super) fn cells(&self) -> usize {
        self.count.len()
    }

    /// Places per cell.
    fn places(&self) -> usize {
        self.blocks * LANES
    }

    /// The cell of a point, wrapped into the box (inside walls, the nearest cell).
    #[inline]
    pub(super) fn cell(&self, p: Vec3) -> [u32; 3] {
        let p = p - self.min;
        let mut c = [0u32; 3];
        for k in 0..3 {
            let w = if self.wrap {
                p[k] - (p[k] * self.inv_side[k]).floor() * self.side[k]
            } else {
                p[k]
            };
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

    /// Where `p` lies as a fraction of the span, wrapped into it.
    #[inline]
    fn fraction(&self, p: Vec3) -> [Real; 3] {
        let x = (p - self.min) / self.span;
        let x = x - x.floor();
        [x.x, x.y, x.z]
    }

    /// Place `k` of cell `c`.
    fn get(&self, c: usize, k: usize) -> Filed {
        let b = &self.placed[c * self.blocks + k / LANES];
        let j = k % LANES;
        Filed {
            at: [b.x[j], b.y[j], b.z[j]],
            id: b.id[j],
        }
    }

    /// Puts `f` in place `k` of cell `c`.
    fn set(&mut self, c: usize, k: usize, f: Filed) {
        let b = &mut self.placed[c * self.blocks + k / LANES];
        let j = k % LANES;
        (b.x[j], b.y[j], b.z[j], b.id[j]) = (f.at[0], f.at[1], f.at[2], f.id);
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
        self.largest_radius = self.largest_radius.max(r);
        let f = Filed {
            at: self.fraction(centre).map(|x| x as f32),
            id,
        };
        let cell = self.index(self.cell(centre));
        let c = cell as usize;
        let k = self.count[c] as usize;
        if k < self.places() {
            self.set(c, k, f);
        } else {
            self.spill.entry(cell).or_default().push(f);
        }
        self.count[c] += 1;
        self.cell_of[id as usize] = cell;
    }

    pub(super) fn remove(&mut self, id: u32) {
        let cell = std::mem::replace(&mut self.cell_of[id as usize], u32::MAX);
        if cell == u32::MAX {
            return;
        }
        let c = cell as usize;
        let k = self.count[c] as usize;
        let places = self.places();
        let held = k.min(places);
        if let Some(at) = (0..held).find(|&j| self.get(c, j).id == id) {
            // The cell's last centre takes the hole: from the spill if it has one.
            let last = if k > places {
                let spill = self.spill.get_mut(&cell).expect("a spilt cell");
                let last = spill.pop().expect("a spilt centre");
                if spill.is_empty() {
                    self.spill.remove(&cell);
                }
                last
            } else {
                let last = self.get(c, held - 1);
                self.set(c, held - 1, Filed::EMPTY);
                last
            };
            if last.id != id {
                self.set(c, at, last);
            }
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

    /// The 27 cells around `c`, with wrap-around (inside walls, the empty cell for those
    /// beyond the box).
    #[inline]
    fn around(&self, c: [u32; 3]) -> [u32; 27] {
        if !self.wrap {
            return self.around_inside(c);
        }
        let n = self.n;
        let mut cells = [0; 27];
        let mut at = 0;
        for dz in [n[2] - 1, 0, 1] {
            let z = (c[2] + dz) % n[2];
            for dy in [n[1] - 1, 0, 1] {
                let y = (c[1] + dy) % n[1];
                let row = self.index([0, y, z]);
                for dx in [n[0] - 1, 0, 1] {
                    cells[at] = row + (c[0] + dx) % n[0];
                    at += 1;
                }
            }
        }
        cells
    }

    /// The 27 cells around `c` inside walls: those beyond the box are the empty last cell.
    fn around_inside(&self, c: [u32; 3]) -> [u32; 27] {
        let empty = (self.count.len() - 1) as u32;
        let step = |x: u32, d: i64, n: u32| -> Option<u32> {
            let y = i64::from(x) + d;
            (0..i64::from(n)).contains(&y).then_some(y as u32)
        };
        let mut cells = [empty; 27];
        let mut at = 0;
        for dz in [-1, 0, 1] {
            for dy in [-1, 0, 1] {
                for dx in [-1, 0, 1] {
                    if let (Some(x), Some(y), Some(z)) = (
                        step(c[0], dx, self.n[0]),
                        step(c[1], dy, self.n[1]),
                        step(c[2], dz, self.n[2]),
                    ) {
                        cells[at] = self.index([x, y, z]);
                    }
                    at += 1;
                }
            }
        }
        cells
    }

    /// Writes to `found` the spheres whose centres, filed in the 27 cells around that of
    /// `centre`, are within `factor` times the sum of their radius and `radius` (nearest
    /// image, plus the rounding margin). The cells' blocks are asked for first, so that they
    /// are fetched together; every place is then tested, and the spheres kept without a
    /// branch on the outcome.
    #[inline]
    pub(super) fn near(&self, centre: Vec3, radius: Real, factor: Real, found: &mut Vec<u32>) {
        let cells = self.around(self.cell(centre));
        for &cell in &cells {
            let at = cell as usize * self.blocks;
            for b in &self.placed[at..at + self.blocks] {
                prefetch(&b.x);
                prefetch(&b.z);
            }
        }
        let mut room = 27 * self.places();
        let spilt = !self.spill.is_empty();
        if spilt {
            for cell in &cells {
                room += self.spill.get(cell).map_or(0, Vec::len);
            }
        }
        found.clear();
        found.resize(room, 0);
        // With radii that differ, every centre within the largest reach is found first, and
        // each is then tested with its own.
        let other = if self.radii_differ {
            self.largest_radius
        } else {
            self.first_radius
        };
        let reach = (radius + Real::from(other)) * factor + self.margin;
        let mut reach2 = (reach * reach) as f32;
        if Real::from(reach2) < reach * reach {
            reach2 = reach2.next_up();
        }
        let me = self.fraction(centre);
        let probe = Probe {
            me: me.map(|x| x as f32),
            side: [self.span.x as f32, self.span.y as f32, self.span.z as f32],
            reach2,
        };
        let mut len = 0;
        for &cell in &cells {
            let at = cell as usize * self.blocks;
            for b in &self.placed[at..at + self.blocks] {
                len = keep_within(b, &probe, found, len);
            }
        }
        if spilt {
            for cell in &cells {
                for f in self.spill.get(cell).map_or(&[][..], Vec::as_slice) {
                    found[len] = f.id;
                    len += usize::from(distance2(me, f, self.span) < reach * reach);
                }
            }
        }
        found.truncate(len);
        if self.radii_differ {
            found.retain(|&k| {
                let f = self.find(self.cell_of[k as usize] as usize, k);
                let reach = (radius + Real::from(self.radius[k as usize])) * factor + self.margin;
                distance2(me, &f, self.span) < reach * reach
            });
        }
    }

    /// Sphere `k`'s centre, filed in cell `c`.
    fn find(&self, c: usize, k: u32) -> Filed {
        let held = (self.count[c] as usize).min(self.places());
        (0..held)
            .map(|j| self.get(c, j))
            .find(|f| f.id == k)
            .or_else(|| {
                let spill = self.spill.get(&(c as u32))?;
                spill.iter().find(|f| f.id == k).copied()
            })
            .expect("a filed centre")
    }

    /// Checks the grid against the centres it should hold (for tests).
    pub(super) fn validate(&self) -> Result<(), String> {
        let mut held = 0;
        let places = self.places();
        for (c, &k) in self.count.iter().enumerate() {
            let spilt = self.spill.get(&(c as u32)).map_or(0, Vec::len);
            let k = k as usize;
            if k != k.min(places) + spilt {
                return Err(format!("grid: cell {c} counts {k}, spills {spilt}"));
            }
            for j in k.min(places)..places {
                let f = self.get(c, j);
                if f.id != u32::MAX || f.at.iter().any(|x| !x.is_nan()) {
                    return Err(format!("grid: cell {c} holds a centre beyond its count"));
                }
            }
            let spill = self
                .spill
                .get(&(c as u32))
                .map(Vec::as_slice)
                .unwrap_or(&[]);
            for f in (0..k.min(places))
                .map(|j| self.get(c, j))
                .chain(spill.iter().copied())
            {
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

/// The squared distance, nearest image, from the fraction `me` to a centre, in double
/// precision.
#[inline]
fn distance2(me: [Real; 3], f: &Filed, side: Vec3) -> Real {
    let mut d2 = 0.0;
    for k in 0..3 {
        let x = me[k] - Real::from(f.at[k]);
        let x = (x - round_near(x)) * side[k];
        d2 += x * x;
    }
    d2
}

/// Rounds an `f32` to the nearest integer, for magnitudes below 2^22: `(x + R) - R`.
const ROUND: f32 = 12_582_912.0; // 1.5 * 2^23

/// Writes the block's spheres to `found` from `len` on, advancing past those whose centres
/// are within the probe's reach (nearest image); returns the new length. Each place's
/// squared distance is `(dx^2 + dy^2) + dz^2`, each `d = (m - c) - round(m - c)` times the
/// side, in single precision; an empty place's is NaN, and is not kept.
#[inline(always)]
fn keep_within(b: &Block, probe: &Probe, found: &mut [u32], len: usize) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        keep_within_sse(b, probe, found, len)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        keep_within_scalar(b, probe, found, len)
    }
}

/// [`keep_within`] one place at a time.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline(always)]
fn keep_within_scalar(b: &Block, probe: &Probe, found: &mut [u32], mut len: usize) -> usize {
    for j in 0..LANES {
        let mut d = [0.0f32; 3];
        for (k, at) in [&b.x, &b.y, &b.z].into_iter().enumerate() {
            let x = probe.me[k] - at[j];
            d[k] = (x - ((x + ROUND) - ROUND)) * probe.side[k];
        }
        let d2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
        found[len] = b.id[j];
        len += usize::from(d2 < probe.reach2);
    }
    len
}

/// [`keep_within`] four places at a time in SSE lanes (part of every x86-64 processor), each
/// lane with the scalar test's operations in order.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn keep_within_sse(b: &Block, probe: &Probe, found: &mut [u32], mut len: usize) -> usize {
    use std::arch::x86_64::*;
    // SAFETY: SSE and SSE2 are part of every x86-64 processor; the loads read four `f32`
    // of a block's 16-byte-aligned rows (a block is aligned to 64, each row 32 bytes).
    #[allow(unsafe_code)]
    unsafe {
        let round = _mm_set1_ps(ROUND);
        let reach2 = _mm_set1_ps(probe.reach2);
        for half in 0..LANES / 4 {
            let at = 4 * half;
            let mut d2 = _mm_setzero_ps();
            for (k, row) in [&b.x, &b.y, &b.z].into_iter().enumerate() {
                let c = _mm_load_ps(row.as_ptr().add(at));
                let x = _mm_sub_ps(_mm_set1_ps(probe.me[k]), c);
                let whole = _mm_sub_ps(_mm_add_ps(x, round), round);
                let d = _mm_mul_ps(_mm_sub_ps(x, whole), _mm_set1_ps(probe.side[k]));
                let dd = _mm_mul_ps(d, d);
                d2 = if k == 0 { dd } else { _mm_add_ps(d2, dd) };
            }
            let mask = _mm_movemask_ps(_mm_cmplt_ps(d2, reach2)) as usize;
            for j in 0..4 {
                found[len] = b.id[at + j];
                len += mask >> j & 1;
            }
        }
    }
    len
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SSE lanes keep exactly what the scalar test keeps, place by place, on blocks of
    /// random centres (empty places, wrap-around and centres on the reach's edge included).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn lanes_keep_what_the_scalar_test_keeps() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut rand = || rng.random_range(0.0f32..1.0);
        let mut kept = 0;
        for round in 0..2000 {
            let mut b = Block::EMPTY;
            for j in 0..LANES - round % 3 {
                (b.x[j], b.y[j], b.z[j], b.id[j]) = (rand(), rand(), rand(), j as u32);
            }
            let probe = Probe {
                me: [rand(), rand(), rand()],
                side: [7.0, 8.5, 9.25],
                reach2: 2.0 + 4.0 * rand(),
            };
            if round % 5 == 0 {
                // A place exactly on the reach along x.
                let x = probe.me[0] - probe.reach2.sqrt() / probe.side[0];
                (b.x[0], b.y[0], b.z[0]) = (x, probe.me[1], probe.me[2]);
            }
            let (mut a, mut s) = ([0u32; LANES], [0u32; LANES]);
            let n = keep_within_sse(&b, &probe, &mut a, 0);
            assert_eq!(
                n,
                keep_within_scalar(&b, &probe, &mut s, 0),
                "round {round}"
            );
            assert_eq!(a[..n], s[..n], "round {round}");
            kept += n;
        }
        assert!(kept > 500, "{kept}");
    }

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
        let mut grid = CentreGrid::new(n, Vec3::splat(-1.0), side, 2.0, true);
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
