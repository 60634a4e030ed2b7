//! Fast objects ([`Grid::with_least_flight`]): a region instead of cells, and their grid
//! pairs with the objects whose zones meet it.

use super::FAST_MARGIN;
use super::{Grid, Member};
use crate::cell_math::{Local, exit_from, swept_box};
use kinetic_core::kds::{PairChange, ordered_pair};
use kinetic_core::{Real, Vec3};

/// Whether two zones (closed boxes, lower and upper corners) meet, give or take rounding.
fn zones_meet(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    (0..3).all(|k| {
        let tol = (1e-9 * ((a.1[k] - a.0[k]) + (b.1[k] - b.0[k]))
            + 1e-12 * (a.0[k].abs() + b.0[k].abs()))
        .max(0.0);
        a.0[k] <= b.1[k] + tol && b.0[k] <= a.1[k] + tol
    })
}

impl Grid {
    /// The ends of the box of `m` around `now`, per axis.
    fn keys_of(m: &Member, now: Real) -> [(Local, Local); 3] {
        std::array::from_fn(|k| (m.lo[k].local(now), m.hi[k].local(now)))
    }

    /// Whether `m` at `now` travels more than `span` of its own level's cells on an axis
    /// within the least flight (never without one).
    pub(super) fn is_fast(&self, m: &Member, now: Real, span: Real) -> bool {
        if self.least_flight <= 0.0 {
            return false;
        }
        let h = self.least_flight;
        let travel = (0..3)
            .map(|k| {
                let c = m.lo[k].local(now);
                c[1].abs() * h + c[2].abs() * h * h
            })
            .fold(0.0, Real::max);
        travel > span * self.cell_size(m.level)
    }

    /// Where member `id` may be: a fast one's region, else the cells of its own track.
    fn zone(&self, id: u32) -> (Vec3, Vec3) {
        let m = self.member(id);
        if let Some(region) = m.region {
            return region;
        }
        let t = &m.tracks[0];
        let s = self.cell_size(t.level);
        let lo = Vec3::from_array(std::array::from_fn(|k| s * t.cells[k][0] as Real));
        let hi = Vec3::from_array(std::array::from_fn(|k| s * (t.cells[k][1] + 1) as Real));
        (lo, hi)
    }

    /// Whether fast member `f` and member `x` are a grid pair: their zones meet.
    pub(super) fn fast_pair(&self, f: u32, x: u32) -> bool {
        zones_meet(self.zone(f), self.zone(x))
    }

    /// Gives fast member `id` (no tracks, in no cell) a fresh region from `now`, makes its
    /// grid pairs those whose zones meet it (reporting the changes) and schedules its exit.
    pub(super) fn anchor_fast(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        self.fast_anchors += 1;
        let m = self.member(id);
        let keys = Self::keys_of(m, now);
        let scale = keys
            .iter()
            .map(|(l, u)| l[0].abs().max(u[0].abs()))
            .fold(0.0, Real::max)
            + m.width;
        let margin = (FAST_MARGIN * m.width)
            .max(1e-9 * scale)
            .max(Real::MIN_POSITIVE);
        let (lo, hi) = swept_box(&keys, self.least_flight, margin);
        let exit = exit_from(&keys, lo, hi, now);
        self.members[id as usize].as_mut().expect("a member").region = Some((lo, hi));
        let want = self.fast_partners(id, lo, hi);
        let m = self.member(id);
        let mut have: Vec<u32> = m
            .pairs
            .iter()
            .map(|&i| {
                let slot = self.slots[i as usize].as_ref().expect("a slot");
                if slot.a == id { slot.b } else { slot.a }
            })
            .collect();
        have.sort_unstable();
        for &p in &have {
            if want.binary_search(&p).is_err() {
                self.pair_down(id, p, changes);
            }
        }
        for &p in &want {
            if have.binary_search(&p).is_err() {
                self.pair_up(id, p, now, changes);
            }
        }
        if exit.is_finite() {
            self.crossings_queue.schedule(id, exit, 0);
        } else {
            self.crossings_queue.remove(id);
        }
    }

    /// The members whose zones meet the region `lo..hi` of fast member `id`, sorted: the
    /// other fast ones, and the owners of the cells around it at every occupied level.
    fn fast_partners(&self, id: u32, lo: Vec3, hi: Vec3) -> Vec<u32> {
        let mut out: Vec<u32> = self
            .fast
            .iter()
            .copied()
            .filter(|&f| f != id && zones_meet(self.zone(f), (lo, hi)))
            .collect();
        let mut owners = Vec::new();
        // Levels whose cells around the region outnumber the cells kept are read from the
        // whole table instead, once.
        let mut whole = Vec::new();
        for &(level, bounds) in &self.owned {
            let s = self.cell_size(level);
            // One cell more on every side, so that a cell whose edge the region touches is
            // read however the division rounds; no farther than any owner has been.
            let range: [[i64; 2]; 3] = std::array::from_fn(|k| {
                [
                    ((lo[k] / s).floor() as i64)
                        .saturating_sub(1)
                        .max(bounds[k][0]),
                    ((hi[k] / s).floor() as i64)
                        .saturating_add(1)
                        .min(bounds[k][1]),
                ]
            });
            if range.iter().any(|[a, b]| a > b) {
                continue;
            }
            let count: Real = range
                .iter()
                .map(|[a, b]| *b as Real - *a as Real + 1.0)
                .product();
            if count > self.cells.len() as Real {
                whole.push((level, range));
                continue;
            }
            for x in range[0][0]..=range[0][1] {
                for y in range[1][0]..=range[1][1] {
                    for z in range[2][0]..=range[2][1] {
                        if let Some(cell) = self.cells.get(&(level, x, y, z)) {
                            owners.extend_from_slice(&cell.owners);
                        }
                    }
                }
            }
        }
        if !whole.is_empty() {
            for (key, cell) in &self.cells {
                let within = whole.iter().any(|(level, r)| {
                    *level == key.0
                        && [key.1, key.2, key.3]
                            .iter()
                            .zip(r)
                            .all(|(c, [a, b])| a <= c && c <= b)
                });
                if within {
                    owners.extend_from_slice(&cell.owners);
                }
            }
        }
        owners.sort_unstable();
        owners.dedup();
        out.extend(
            owners
                .into_iter()
                .filter(|&x| x != id && zones_meet(self.zone(x), (lo, hi))),
        );
        out.sort_unstable();
        out
    }

    /// Makes the grid pairs of member `id`, which lives in cells, with the fast members those
    /// whose regions meet its own-level cells (after its own track changed).
    pub(super) fn fast_links(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        for i in 0..self.fast.len() {
            let f = self.fast[i];
            let want = self.fast_pair(f, id);
            let have = self.pair_of.contains_key(&ordered_pair(f, id));
            if want && !have {
                self.pair_up(f, id, now, changes);
            } else if have && !want {
                self.pair_down(f, id, changes);
            }
        }
    }
}
