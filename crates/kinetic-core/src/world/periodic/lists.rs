//! Neighbour lists (a fixed stride per sphere, grown when a list overflows) and the cell grid
//! of list centres they are made from.

use super::NIL;
use crate::math::{Real, Vec3};

/// Every sphere's neighbours, `stride` slots each.
#[derive(Clone, Debug)]
pub(super) struct Lists {
    stride: usize,
    len: Vec<u16>,
    slots: Vec<u32>,
    total: usize,
}

const EMPTY: u32 = NIL;

impl Lists {
    pub(super) fn new(spheres: usize, stride: usize) -> Lists {
        let stride = stride.clamp(4, u16::MAX as usize);
        Lists {
            stride,
            len: vec![0; spheres],
            slots: vec![EMPTY; spheres * stride],
            total: 0,
        }
    }

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
        &self.slots[at..at + self.len[i as usize] as usize]
    }

    pub(super) fn push(&mut self, i: u32, n: u32) {
        if self.len[i as usize] as usize == self.stride {
            self.grow();
        }
        let l = &mut self.len[i as usize];
        self.slots[i as usize * self.stride + *l as usize] = n;
        *l += 1;
        self.total += 1;
    }

    /// Removes `other` from `i`'s list (order is not kept).
    pub(super) fn remove(&mut self, i: u32, other: u32) {
        let at = i as usize * self.stride;
        let l = self.len[i as usize] as usize;
        if let Some(k) = self.slots[at..at + l].iter().position(|&n| n == other) {
            self.slots[at + k] = self.slots[at + l - 1];
            self.len[i as usize] -= 1;
            self.total -= 1;
        }
    }

    pub(super) fn clear(&mut self, i: u32) {
        self.total -= self.len[i as usize] as usize;
        self.len[i as usize] = 0;
    }

    /// Doubles the stride (a list is full): every list moves to its new place.
    fn grow(&mut self) {
        let stride = (self.stride * 2).min(u16::MAX as usize);
        assert!(
            stride > self.stride,
            "a neighbour list holds at most 65535 spheres"
        );
        let mut slots = vec![EMPTY; self.len.len() * stride];
        for (i, &l) in self.len.iter().enumerate() {
            let from = i * self.stride;
            slots[i * stride..i * stride + l as usize]
                .copy_from_slice(&self.slots[from..from + l as usize]);
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

    /// Calls `f` on each centre filed in the 27 cells around `c` (with wrap-around).
    #[inline]
    pub(super) fn for_each_around(&self, c: [u32; 3], mut f: impl FnMut(&Filed)) {
        let n = self.n;
        for dz in [n[2] - 1, 0, 1] {
            let z = (c[2] + dz) % n[2];
            for dy in [n[1] - 1, 0, 1] {
                let y = (c[1] + dy) % n[1];
                for dx in [n[0] - 1, 0, 1] {
                    let x = (c[0] + dx) % n[0];
                    self.cells[self.index([x, y, z]) as usize]
                        .iter()
                        .for_each(&mut f);
                }
            }
        }
    }
}
