//! The stepped grid: the pairs of a set of boxes whose boxes overlap, found from scratch.
//!
//! Boxes are rounded outwards to single precision. Cells are as wide as the widest *small*
//! box (at most [`SMALL`] times the median box), so a small box overlaps at most two cells a
//! side and two small boxes that overlap have their centres in the same cell or in
//! neighbouring ones. The boxes are sorted by table slot with a counting sort, each with a
//! copy of its box, so that a slot's boxes lie together in memory:
//!
//! - **Dense** (the boxes' cells fill a table of at most [`DENSE_CELLS`] slots a box: a pile,
//!   a rain, a gas): each small box is filed once, in the cell of its centre, and tested
//!   against the boxes of its own cell and of the 13 neighbouring cells after it (each pair
//!   of cells once), which lie in five runs of the table.
//! - **Hashed** (boxes scattered over a space far wider than they fill: debris flying
//!   apart): the cells are hashed into a table about [`HASHED_SLOTS`] times as long as the
//!   boxes, and each small box is filed in every cell it overlaps. Boxes are tested only
//!   within a slot, and a pair is taken in the cell of the upper of their lower corners, so
//!   an empty neighbourhood costs nothing (looking up 13 neighbouring cells a box cost the
//!   scattered burst twice as much).
//!
//! The grid of another's wide boxes (below) is always hashed: the smaller boxes look it up
//! far more than it finds pairs of its own.
//!
//! A wider box looks up the cells its overlapping small boxes can be filed in, and one too
//! wide for [`WIDE_CELLS`] cells (a ground, a wall) is tested against every box; the wide
//! ones are tested against each other. Cells that hash alike cost only tests: pairs found
//! twice are deduplicated. Nothing is allocated once the buffers have grown.
//!
//! A few boxes, or boxes that overlap few others along some axis (debris), are sorted and
//! swept instead ([`super::sweep`]): below a few hundred boxes a grid's fixed costs outweigh
//! its few tests.

use super::sweep::SortAndSweep;
use crate::aabb::{Aabb, AabbF32, overlap, to_f32, width};
use glam::Vec3A;
use kinetic_core::floor_int;

/// A box at most this many times the median box's widest side is small...
const SMALL: f32 = 2.0;
/// ... or this many in the grid of another's wide boxes: a spread of sizes nests fewer
/// grids (debris of radii 0.01 to 10 filed 12% faster than with [`SMALL`]).
const INNER_SMALL: f32 = 8.0;
/// A wide box looks up at most this many cells; a wider one is tested against every box.
const WIDE_CELLS: i64 = 4096;
/// ... and at most this many cells a filed box: in a small world a ground or a wall spans
/// more cells than there are boxes, and testing each box costs less than looking up each cell.
const CELLS_A_BOX: i64 = 2;
/// The cells are not hashed while there are at most this many a box (a table of every
/// cell, whose neighbours lie next to each other in memory).
const DENSE_CELLS: i64 = 32;
/// Wide boxes are tested among themselves in a grid of their own above this many.
const INNER_FROM: usize = 32;
/// The median is taken again every this many calls.
const MEDIAN_EVERY: u32 = 16;
/// A hashed table has about this many slots a box (a box is filed in up to eight cells).
const HASHED_SLOTS: usize = 4;
/// At most this many boxes are always sorted and swept ([`SortAndSweep`]) rather than filed...
const SWEEP_ALWAYS: usize = 256;
/// ... up to this many while the sweep tests at most [`SWEEP_TESTS`] pairs a box (without
/// this bound worlds of 1e4 bodies were within noise, and a sweep that gives up has sorted
/// every box first)...
const SWEEP_MOST: usize = 2048;
/// ... (debris: 3 a box; a pile, a rain or a gas of 400 bodies: 20 to 32, where the sweep
/// costs about what the grid does; of 1e3: 50 to 70, where a pile's sweep costs a fifth
/// more)...
const SWEEP_TESTS: usize = 16;
/// ... and it is tried again this many calls after it tested more.
const SWEEP_AGAIN: u32 = 64;

/// The grid's reused buffers.
#[derive(Clone, Debug, Default)]
pub(crate) struct SteppedGrid {
    /// The widest side of a small box, and the inverse of a cell's side (0: none yet),
    /// a cell a little wider than the widest small box.
    widest: f32,
    inv: f64,
    /// The median box's widest side, and the calls since it was taken.
    median: f32,
    calls: u32,
    /// The grid for the wide boxes among themselves, when there are many.
    inner: Option<Box<SteppedGrid>>,
    /// The table's length less one (a power of two less one), when the cells are hashed.
    mask: u32,
    /// When the cells are not hashed: the least cell and the grid's size in cells (the
    /// table holds every cell, `z` fastest, then `y`, then `x`).
    dense: Option<([i64; 3], [i64; 3])>,
    /// Per slot, where its boxes start in `sorted` (and one past the last slot).
    starts: Vec<u32>,
    /// The slots that hold boxes (the only ones whose runs are looked at).
    occupied: Vec<u32>,
    /// The small boxes' slots, then the small boxes (and their places) by slot.
    slots: Vec<(u32, u32)>,
    sorted: Vec<(AabbF32, u32)>,
    /// This call's wide boxes, and each box's cell (`None`: wide).
    wide: Vec<u32>,
    cells: Vec<Option<[i64; 3]>>,
    /// Whether the table holds this call's boxes (not when there were fewer than two).
    built: bool,
    /// Whether `inner` holds this call's wide boxes.
    nesting: bool,
    /// Whether it is the grid of another's wide boxes.
    nested_in: bool,
    /// This call's boxes and their ids.
    boxes: Vec<AabbF32>,
    ids: Vec<u32>,
    /// Scratch for the median.
    widths: Vec<f32>,
    /// Scratch for sorting the pairs: where each first id's pairs start, and the pairs.
    pair_starts: Vec<u32>,
    pair_scratch: Vec<(u32, u32)>,
    /// The sort and sweep, whether it gave this call's pairs, and the calls before it is
    /// tried again.
    sweep: SortAndSweep,
    swept: bool,
    sweep_wait: u32,
    /// Never swept (the tests of the grid itself).
    no_sweep: bool,
}

impl SteppedGrid {
    /// The cell holding point `p`.
    fn cell_of(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|x| floor_int(x * self.inv))
    }

    /// The cell of box `b`'s centre.
    fn centre_cell(&self, b: &AabbF32) -> [i64; 3] {
        self.cell_of(std::array::from_fn(|k| {
            (b[0][k] as f64 + b[1][k] as f64) / 2.0
        }))
    }

    /// The table slot of cell `c` (in a dense table, a cell outside the grid gets a slot
    /// past the last, whose run is empty).
    fn slot(&self, c: [i64; 3]) -> u32 {
        if let Some((lo, n)) = self.dense {
            let d: [i64; 3] = std::array::from_fn(|k| c[k] - lo[k]);
            if (0..3).any(|k| d[k] < 0 || d[k] >= n[k]) {
                return self.mask + 1;
            }
            return ((d[0] * n[1] + d[1]) * n[2] + d[2]) as u32;
        }
        let h = (c[0] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (c[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (c[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
        ((h >> 32) as u32) & self.mask
    }

    /// The boxes filed in slots `s..t`, for slots past the last none.
    fn runs(&self, s: u32, t: u32) -> &[(AabbF32, u32)] {
        let last = self.mask as usize + 1;
        let (s, t) = ((s as usize).min(last), (t as usize).min(last));
        &self.sorted[self.starts[s] as usize..self.starts[t.max(s)] as usize]
    }

    /// The boxes filed in slot `s`.
    fn run(&self, s: u32) -> &[(AabbF32, u32)] {
        self.runs(s, s + 1)
    }

    /// A grid that never sorts and sweeps: one that is looked up far more than it is filed
    /// (a sweep's look-up passes over every box below the one looked up).
    pub(crate) fn for_lookups() -> SteppedGrid {
        SteppedGrid {
            no_sweep: true,
            ..SteppedGrid::default()
        }
    }

    /// Takes the median box again at the next call, in the nested grids too: the boxes to
    /// come are of another kind (fat boxes after plain ones, or fatter ones).
    pub(crate) fn remeasure(&mut self) {
        self.median = 0.0;
        if let Some(inner) = self.inner.as_deref_mut() {
            inner.remeasure();
        }
    }

    /// Pushes onto `out` the ids of the last call's boxes that overlap `q` as the grid
    /// tests a pair (a box may come more than once).
    pub(crate) fn overlapping_with(&self, q: &Aabb, out: &mut Vec<u32>) {
        self.query(&to_f32(q), &mut |id| out.push(id));
    }

    /// Calls `hit` with the id of each of the last call's boxes that overlaps `q` (a box may
    /// come more than once): the small boxes filed in the cells `q` reaches, and the wide
    /// ones from their own grid when they have one.
    fn query(&self, q: &AabbF32, hit: &mut impl FnMut(u32)) {
        if self.swept {
            self.sweep
                .query(&self.boxes, q, |j| hit(self.ids[j as usize]));
            return;
        }
        if !self.built {
            for (b, id) in self.boxes.iter().zip(&self.ids) {
                if overlap(q, b) {
                    hit(*id);
                }
            }
            return;
        }
        self.filed_overlapping(q, |j| hit(self.ids[j as usize]));
        match self.nested() {
            Some(inner) => inner.query(q, hit),
            None => {
                for &w in &self.wide {
                    if overlap(q, &self.boxes[w as usize]) {
                        hit(self.ids[w as usize]);
                    }
                }
            }
        }
    }

    /// The grid of this call's wide boxes, when they have one.
    fn nested(&self) -> Option<&SteppedGrid> {
        self.inner.as_deref().filter(|_| self.nesting)
    }

    /// Calls `hit` with the place of each small box filed in the table that overlaps `q`
    /// (a box may come more than once): from the cells `q` reaches, or from every small box
    /// when those are more than [`WIDE_CELLS`].
    fn filed_overlapping(&self, q: &AabbF32, mut hit: impl FnMut(u32)) {
        // Dense: small boxes are filed by their centres, half a cell from their edges.
        let half = if self.dense.is_some() {
            0.5 / self.inv
        } else {
            0.0
        };
        let mut lo = self.cell_of(std::array::from_fn(|k| q[0][k] as f64 - half));
        let mut hi = self.cell_of(std::array::from_fn(|k| q[1][k] as f64 + half));
        if let Some((least, n)) = self.dense {
            // Only the grid's own cells hold boxes.
            for k in 0..3 {
                lo[k] = lo[k].max(least[k]);
                hi[k] = hi[k].min(least[k] + n[k] - 1);
            }
            // A query wholly outside the grid meets none (a row's run must not reach past it).
            if (0..3).any(|k| lo[k] > hi[k]) {
                return;
            }
        }
        let cells = (0..3)
            .map(|k| hi[k].saturating_sub(lo[k]).saturating_add(1).max(0))
            .fold(1i64, |p, x| p.saturating_mul(x));
        let mut test = |run: &[(AabbF32, u32)]| {
            for (b, j) in run {
                if overlap(q, b) {
                    hit(*j);
                }
            }
        };
        if cells > WIDE_CELLS.min(CELLS_A_BOX * self.sorted.len() as i64) {
            test(&self.sorted);
            return;
        }
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                if self.dense.is_some() {
                    // A row of cells along z lies in one run of the table.
                    let (s, t) = (self.slot([x, y, lo[2]]), self.slot([x, y, hi[2]]));
                    test(self.runs(s, t + 1));
                    continue;
                }
                for z in lo[2]..=hi[2] {
                    test(self.run(self.slot([x, y, z])));
                }
            }
        }
    }

    /// Whether the small boxes' cells make a table of at most [`DENSE_CELLS`] slots a box: the
    /// grid's least cell and size in cells, if so.
    fn dense_grid(&self) -> Option<([i64; 3], [i64; 3])> {
        let mut lo = [i64::MAX; 3];
        let mut hi = [i64::MIN; 3];
        for c in self.cells.iter().flatten() {
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        let n: [i64; 3] = std::array::from_fn(|k| hi[k].saturating_sub(lo[k]).saturating_add(1));
        let cells = n.iter().try_fold(1i64, |p, &x| p.checked_mul(x.max(1)))?;
        (lo[0] <= hi[0] && cells <= DENSE_CELLS * self.boxes.len() as i64 + 64).then_some((lo, n))
    }

    /// Puts the pairs `(a, b)`, `a < b`, of `items` (`(id, box)`, ids distinct) whose boxes
    /// overlap and that `keep(a, b)` keeps into `out`, sorted; what `out` held is cleared.
    pub(crate) fn pairs(
        &mut self,
        items: impl IntoIterator<Item = (u32, Aabb)>,
        keep: &dyn Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
    ) {
        out.clear();
        self.boxes.clear();
        self.ids.clear();
        for (id, b) in items {
            self.ids.push(id);
            self.boxes.push(to_f32(&b));
        }
        self.find(keep, out);
        self.sort(out);
        out.dedup();
    }

    /// Files `items` (`(id, box)`, ids distinct) for look-ups ([`Self::overlapping_with`])
    /// without looking for their pairs.
    pub(crate) fn file_for_lookups(&mut self, items: impl IntoIterator<Item = (u32, Aabb)>) {
        self.boxes.clear();
        self.ids.clear();
        for (id, b) in items {
            self.ids.push(id);
            self.boxes.push(to_f32(&b));
        }
        self.built = false;
        self.nesting = false;
        self.swept = false;
        if self.boxes.len() >= 2 {
            self.file();
        }
    }

    /// Sorts `pairs` of this call's ids as tuples sort. Where the pairs are many against the
    /// ids (a pile, a rain), by a counting sort on the first id and each first id's few
    /// pairs in place; where they are few (debris), by comparison.
    fn sort(&mut self, pairs: &mut Vec<(u32, u32)>) {
        if pairs.len() < 2 {
            return;
        }
        let top = self.ids.iter().max().map_or(0, |&m| m as usize + 1);
        if pairs.len() * 8 < top {
            pairs.sort_unstable_by_key(|&(a, b)| (u64::from(a) << 32) | u64::from(b));
            return;
        }
        let starts = &mut self.pair_starts;
        starts.clear();
        starts.resize(top + 1, 0);
        for &(a, _) in pairs.iter() {
            starts[a as usize + 1] += 1;
        }
        let mut sum = 0;
        for start in starts.iter_mut() {
            sum += *start;
            *start = sum;
        }
        let sorted = &mut self.pair_scratch;
        sorted.clear();
        sorted.resize(pairs.len(), (0, 0));
        for &p in pairs.iter() {
            let at = &mut starts[p.0 as usize];
            sorted[*at as usize] = p;
            *at += 1;
        }
        // `starts[a]` is now where the pairs of `a + 1` start: each run ends there.
        let mut from = 0;
        for &end in starts[..top].iter() {
            sorted[from..end as usize].sort_unstable_by_key(|p| p.1);
            from = end as usize;
        }
        std::mem::swap(pairs, sorted);
    }

    /// Pushes onto `out` the pairs of this call's boxes that `keep` keeps, in no order and
    /// some more than once (the nested grids' pairs go onto the same `out`).
    fn find(&mut self, keep: &dyn Fn(u32, u32) -> bool, out: &mut Vec<(u32, u32)>) {
        self.built = false;
        self.nesting = false;
        self.swept = false;
        let n = self.boxes.len();
        if n < 2 {
            return;
        }
        // A few boxes, or boxes that overlap few others along some axis (debris): sorted and
        // swept, while it takes few tests a box; otherwise filed (and swept again now and
        // then). Pairs a sweep gave up on come again from the grid, and go with the
        // duplicates. Not the grid of another's wide boxes: the smaller boxes look it up far
        // more than it finds pairs of its own, and a look-up in the sweep costs more (a rain
        // of 1e4 bodies a fifth more).
        let few = n <= SWEEP_ALWAYS || (n <= SWEEP_MOST && self.sweep_wait == 0);
        if few && !self.no_sweep && !self.nested_in {
            let budget = if n <= SWEEP_ALWAYS {
                usize::MAX
            } else {
                SWEEP_TESTS * n
            };
            let ids = &self.ids;
            self.swept = self.sweep.pairs(&self.boxes, budget, |i, j| {
                push(out, keep, ids[i as usize], ids[j as usize]);
            });
            if self.swept {
                return;
            }
            self.sweep_wait = SWEEP_AGAIN;
        } else {
            self.sweep_wait = self.sweep_wait.saturating_sub(1);
        }
        self.file();
        // Small against small: within a cell, and with the cells after it.
        let test = |a: &AabbF32, i: u32, run: &[(AabbF32, u32)], out: &mut Vec<(u32, u32)>| {
            for (b, j) in run {
                // A box whose cells hash alike is filed twice in a slot.
                if overlap(a, b) && i != *j {
                    push(out, keep, self.ids[i as usize], self.ids[*j as usize]);
                }
            }
        };
        match self.dense {
            // In a dense table the 13 cells after a cell lie in 5 runs of slots: the next
            // cell, then three rows of three (slots past a row's end only add tests).
            Some((_, n)) => {
                let (row, slab) = (n[2], n[1] * n[2]);
                for &s in &self.occupied {
                    let run = self.run(s);
                    let t = s as i64;
                    let from = [
                        t + 1,
                        t + row - 1,
                        t + slab - row - 1,
                        t + slab - 1,
                        t + slab + row - 1,
                    ];
                    let near: [&[(AabbF32, u32)]; 5] = std::array::from_fn(|r| {
                        let f = from[r];
                        let e = if r == 0 { f + 1 } else { f + 3 };
                        self.runs(f.max(0) as u32, e.max(0) as u32)
                    });
                    for (k, (a, i)) in run.iter().enumerate() {
                        test(a, *i, &run[k + 1..], out);
                        for r in near {
                            test(a, *i, r, out);
                        }
                    }
                }
            }
            // Hashed: boxes meet only within a cell they share, and a pair is taken in one of
            // them, the cell of the upper of their lower corners (both overlap it when they
            // overlap). Cells that hash alike may still give a pair twice.
            None => {
                for &s in &self.occupied {
                    let run = self.run(s);
                    for (k, (a, i)) in run.iter().enumerate() {
                        for (b, j) in &run[k + 1..] {
                            if overlap(a, b) && i != j {
                                let corner = a[0].max(b[0]);
                                let home = self.cell_of(std::array::from_fn(|k| corner[k] as f64));
                                if self.slot(home) == s {
                                    push(out, keep, self.ids[*i as usize], self.ids[*j as usize]);
                                }
                            }
                        }
                    }
                }
            }
        }
        // Many wide boxes (a spread of sizes) meet each other in a grid of their own, and each
        // small box looks up the few cells of that grid it reaches (and so on up the sizes),
        // unless none of them came out small (boxes with NaN sides) and it would never end.
        if self.wide.len() > INNER_FROM {
            let mut inner = self.inner.take().unwrap_or_default();
            inner.nested_in = true;
            inner.no_sweep = self.no_sweep;
            inner.boxes.clear();
            inner.ids.clear();
            for &w in &self.wide {
                inner.boxes.push(self.boxes[w as usize]);
                inner.ids.push(self.ids[w as usize]);
            }
            if self.wide.len() < self.boxes.len() {
                inner.find(keep, out);
            } else {
                inner.built = false;
                for (k, a) in inner.boxes.iter().enumerate() {
                    for (l, b) in inner.boxes.iter().enumerate().skip(k + 1) {
                        if overlap(a, b) {
                            push(out, keep, inner.ids[k], inner.ids[l]);
                        }
                    }
                }
            }
            self.inner = Some(inner);
            self.nesting = true;
            let inner = self.inner.as_deref().expect("just put");
            for (i, c) in self.cells.iter().enumerate() {
                if c.is_some() {
                    let id = self.ids[i];
                    inner.query(&self.boxes[i], &mut |j| push(out, keep, id, j));
                }
            }
        } else {
            // A few wide boxes: against the small boxes whose centres can lie near (dense) or
            // that are filed in its cells (hashed), or against all, and against each other.
            for (n, &w) in self.wide.iter().enumerate() {
                let a = self.boxes[w as usize];
                let id = self.ids[w as usize];
                self.filed_overlapping(&a, |j| push(out, keep, id, self.ids[j as usize]));
                for &v in &self.wide[n + 1..] {
                    if overlap(&a, &self.boxes[v as usize]) {
                        push(out, keep, id, self.ids[v as usize]);
                    }
                }
            }
        }
    }

    /// Files this call's boxes: the small ones in the table by slot, the others listed as
    /// wide.
    fn file(&mut self) {
        self.choose_cell();
        // Small boxes and their slots; the others are wide (a NaN box too: it meets none).
        self.wide.clear();
        self.slots.clear();
        let limit = self.widest;
        // Each small box's cell (`None`: a wide box).
        self.cells.clear();
        for b in &self.boxes {
            let small = width(b) <= limit;
            self.cells.push(small.then(|| self.centre_cell(b)));
        }
        // A grid of another's wide boxes is looked up by the smaller boxes far more than it
        // finds pairs of its own: hashed, a look-up reads the cells a box overlaps (one or
        // two a side), not those around it (two or three a side).
        self.dense = if self.nested_in {
            None
        } else {
            self.dense_grid()
        };
        let len = match self.dense {
            Some((_, n)) => (n[0] * n[1] * n[2]) as usize,
            None => (HASHED_SLOTS * self.boxes.len()).next_power_of_two(),
        };
        self.mask = len as u32 - 1;
        for (i, c) in self.cells.iter().enumerate() {
            match c {
                // Dense: in the cell of its centre.
                Some(c) if self.dense.is_some() => self.slots.push((self.slot(*c), i as u32)),
                // Hashed: in every cell it overlaps (at most two a side: a cell is wider
                // than a small box).
                Some(_) => {
                    let b = &self.boxes[i];
                    let lo = self.cell_of(std::array::from_fn(|k| b[0][k] as f64));
                    let hi = self.cell_of(std::array::from_fn(|k| b[1][k] as f64));
                    for x in lo[0]..=hi[0] {
                        for y in lo[1]..=hi[1] {
                            for z in lo[2]..=hi[2] {
                                self.slots.push((self.slot([x, y, z]), i as u32));
                            }
                        }
                    }
                }
                None => self.wide.push(i as u32),
            }
        }
        // Counting sort by slot.
        self.starts.clear();
        self.starts.resize(len + 1, 0);
        self.occupied.clear();
        for &(s, _) in &self.slots {
            let count = &mut self.starts[s as usize + 1];
            if *count == 0 {
                self.occupied.push(s);
            }
            *count += 1;
        }
        // Summed in a register: each slot's count is read once, not reloaded as just stored.
        let mut sum = 0;
        for start in &mut self.starts {
            sum += *start;
            *start = sum;
        }
        // Every place is written below: no need to clear it first.
        self.sorted.resize(self.slots.len(), ([Vec3A::ZERO; 2], 0));
        for &(s, i) in &self.slots {
            let at = &mut self.starts[s as usize];
            self.sorted[*at as usize] = (self.boxes[i as usize], i);
            *at += 1;
        }
        // `starts[s]` is where slot `s + 1` starts: shift back.
        self.starts.copy_within(0..len, 1);
        self.starts[0] = 0;
        self.built = true;
    }

    /// Chooses the cell size: the widest small box, small by the median box taken every
    /// [`MEDIAN_EVERY`] calls.
    fn choose_cell(&mut self) {
        if self.median == 0.0 || self.calls >= MEDIAN_EVERY {
            self.calls = 0;
            self.widths.clear();
            self.widths.extend(
                self.boxes
                    .iter()
                    .map(width)
                    .filter(|w| w.is_finite() && *w > 0.0),
            );
            self.median = if self.widths.is_empty() {
                1.0
            } else {
                let mid = self.widths.len() / 2;
                *self.widths.select_nth_unstable_by(mid, f32::total_cmp).1
            };
        }
        self.calls += 1;
        let limit = if self.nested_in { INNER_SMALL } else { SMALL } * self.median;
        self.widest = self
            .boxes
            .iter()
            .map(width)
            .filter(|&w| w <= limit)
            .fold(self.median, f32::max);
        // Two small boxes that overlap have centres less than a cell apart on each axis,
        // whatever the rounding of a cell's coordinates: their cells are neighbours.
        self.inv = 1.0 / (self.widest as f64 * 1.001);
    }
}

/// `(a, b)` with the lower first.
fn ordered(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Puts pair `(a, b)` into `out`, lower first, if `keep` keeps it.
fn push(out: &mut Vec<(u32, u32)>, keep: &dyn Fn(u32, u32) -> bool, a: u32, b: u32) {
    let p = ordered(a, b);
    if keep(p.0, p.1) {
        out.push(p);
    }
}

#[cfg(test)]
#[path = "grid_tests.rs"]
pub(crate) mod tests;
