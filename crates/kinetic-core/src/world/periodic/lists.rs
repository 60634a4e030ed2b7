//! Neighbour lists (a fixed stride per sphere, grown when a list overflows) and the cell grid
//! of list centres they are made from.

use crate::math::{Real, Vec3};
use crate::prefetch::prefetch;

/// Every sphere's neighbours, in a row of `stride` slots each: the row's first slot holds the
/// list's length, the others its neighbours, so that a list is one or two cache lines.
#[derive(Clone, Debug)]
pub(super) struct Lists {
    stride: usize,
    slots: Vec<u32>,
    total: usize,
    /// Per sphere, the last stamp a relist gave it (see [`Lists::stamps`]), and the next
    /// stamp to give.
    stamp: Vec<u32>,
    next_stamp: u32,
    /// The row being relisted, as it was.
    old: Vec<u32>,
}

impl Lists {
    pub(super) fn new(spheres: usize, stride: usize) -> Lists {
        let stride = stride.clamp(4, u16::MAX as usize);
        Lists {
            stride,
            slots: vec![0; spheres * stride],
            total: 0,
            stamp: vec![0; spheres],
            next_stamp: 1,
            old: Vec::new(),
        }
    }

    /// Slots per row (one more than a list can hold before the rows grow).
    pub(super) fn stride(&self) -> usize {
        self.stride
    }

    /// Entries over all lists (each pair twice).
    pub(super) fn total(&self) -> usize {
        self.total
    }

    #[inline]
    pub(super) fn of(&self, i: u32) -> &[u32] {
        let at = i as usize * self.stride;
        let len = self.slots[at] as usize;
        &self.slots[at + 1..at + 1 + len]
    }

    /// Asks for `i`'s row to be fetched (its first two cache lines).
    #[inline]
    pub(super) fn prefetch(&self, i: u32) {
        let at = i as usize * self.stride;
        prefetch(&self.slots[at]);
        if let Some(later) = self.slots.get(at + 16) {
            prefetch(later);
        }
    }

    pub(super) fn push(&mut self, i: u32, n: u32) {
        let mut at = i as usize * self.stride;
        if self.slots[at] as usize + 1 == self.stride {
            self.grow();
            at = i as usize * self.stride;
        }
        let len = self.slots[at] as usize;
        self.slots[at + 1 + len] = n;
        self.slots[at] += 1;
        self.total += 1;
    }

    /// Removes `other` from `i`'s list (order is not kept).
    pub(super) fn remove(&mut self, i: u32, other: u32) {
        let at = i as usize * self.stride;
        let len = self.slots[at] as usize;
        let row = &mut self.slots[at + 1..at + 1 + len];
        if let Some(k) = row.iter().position(|&n| n == other) {
            row[k] = row[len - 1];
            self.slots[at] -= 1;
            self.total -= 1;
        }
    }

    /// Starts relisting `i`: keeps its row as it was and stamps each sphere on it `was`;
    /// [`Lists::restamp`] then stamps those found again `kept`. Returns `(was, kept)`.
    pub(super) fn stamps(&mut self, i: u32) -> (u32, u32) {
        if self.next_stamp >= u32::MAX - 2 {
            self.stamp.fill(0);
            self.next_stamp = 1;
        }
        let (was, kept) = (self.next_stamp, self.next_stamp + 1);
        self.next_stamp += 2;
        let mut old = std::mem::take(&mut self.old);
        old.clear();
        old.extend_from_slice(self.of(i));
        for &k in &old {
            self.stamp[k as usize] = was;
            // Its row is written below if it leaves.
            self.prefetch(k);
        }
        self.old = old;
        (was, kept)
    }

    /// Whether `other` was on the row being relisted (stamped `was`): if so, it is stamped
    /// `kept` and its own row stays as it is.
    #[inline]
    pub(super) fn restamp(&mut self, other: u32, was: u32, kept: u32) -> bool {
        let s = &mut self.stamp[other as usize];
        if *s == was {
            *s = kept;
            true
        } else {
            false
        }
    }

    /// Ends relisting `i`: the spheres on its old row that were not found again (still
    /// stamped `was`) lose it from their rows.
    pub(super) fn drop_left(&mut self, i: u32, was: u32) {
        let old = std::mem::take(&mut self.old);
        for &k in &old {
            if self.stamp[k as usize] == was {
                self.remove(k, i);
            }
        }
        self.old = old;
    }

    pub(super) fn clear(&mut self, i: u32) {
        let at = i as usize * self.stride;
        self.total -= self.slots[at] as usize;
        self.slots[at] = 0;
    }

    /// Doubles the stride (a list is full): every row moves to its new place.
    fn grow(&mut self) {
        let stride = (self.stride * 2).min(u16::MAX as usize);
        assert!(
            stride > self.stride,
            "a neighbour list holds at most 65534 spheres"
        );
        let spheres = self.slots.len() / self.stride;
        let mut slots = vec![0; spheres * stride];
        for i in 0..spheres {
            let from = i * self.stride;
            let used = self.slots[from] as usize + 1;
            slots[i * stride..i * stride + used].copy_from_slice(&self.slots[from..from + used]);
        }
        self.slots = slots;
        self.stride = stride;
    }
}

/// A list centre as the grid files it: where, the sphere's radius, which sphere.
#[derive(Clone, Copy, Debug)]
pub(super) struct Filed {
    pub(super) centre: Vec3,
    pub(super) radius: Real,
    pub(super) id: u32,
}

/// A uniform grid over one period of the box, each cell holding the list centres that lie in
/// it (with the radii, so listing reads one place per candidate).
#[derive(Clone, Debug)]
pub(super) struct CentreGrid {
    pub(super) n: [u32; 3],
    cells: Vec<Vec<Filed>>,
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
        CentreGrid {
            n,
            cells: vec![Vec::new(); cells],
            cell_of: vec![u32::MAX; spheres],
            scale: Vec3::new(n[0] as Real, n[1] as Real, n[2] as Real) / side,
            min,
            side,
            inv_side: Vec3::ONE / side,
        }
    }

    pub(super) fn cells(&self) -> usize {
        self.cells.len()
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
    pub(super) fn index(&self, c: [u32; 3]) -> u32 {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    pub(super) fn insert(&mut self, id: u32, centre: Vec3, radius: Real) {
        let cell = self.index(self.cell(centre));
        self.cells[cell as usize].push(Filed { centre, radius, id });
        self.cell_of[id as usize] = cell;
    }

    pub(super) fn remove(&mut self, id: u32) {
        let cell = &mut self.cells[self.cell_of[id as usize] as usize];
        if let Some(k) = cell.iter().position(|f| f.id == id) {
            cell.swap_remove(k);
        }
        self.cell_of[id as usize] = u32::MAX;
    }

    /// Calls `f` on each centre filed in the 27 cells around `c` (with wrap-around). The
    /// cells are found first and their centres asked for, so that they are fetched together.
    #[inline]
    pub(super) fn for_each_around(&self, c: [u32; 3], mut f: impl FnMut(&Filed)) {
        let n = self.n;
        let mut around: [&[Filed]; 27] = [&[]; 27];
        let mut at = 0;
        for dz in [n[2] - 1, 0, 1] {
            let z = (c[2] + dz) % n[2];
            for dy in [n[1] - 1, 0, 1] {
                let y = (c[1] + dy) % n[1];
                for dx in [n[0] - 1, 0, 1] {
                    let x = (c[0] + dx) % n[0];
                    around[at] = &self.cells[self.index([x, y, z]) as usize];
                    at += 1;
                }
            }
        }
        for first in around.iter().filter_map(|cell| cell.first()) {
            prefetch(first);
        }
        for cell in around {
            cell.iter().for_each(&mut f);
        }
    }
}
