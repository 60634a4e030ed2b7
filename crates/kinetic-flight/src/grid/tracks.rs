//! Footprints: the cells an object covers at each of its levels, and the certificates that
//! keep them (derived tracks follow the own track without certificates).

use super::{CellKey, Grid, HYSTERESIS, HYSTERESIS_ABS, Member, Track};
use crate::cell_math::{crossing, sign_after};
use kinetic_core::Real;

impl Grid {
    /// The footprint of `m` at `level` at time `now`, certificates not yet computed.
    pub(super) fn footprint(&self, m: &Member, level: i32, now: Real) -> Track {
        let s = self.cell_size(level);
        let mut cells = [[0i64; 2]; 3];
        for (k, c) in cells.iter_mut().enumerate() {
            let (lo, hi) = (m.lo[k].local(now), m.hi[k].local(now));
            let mut a = (lo[0] / s).floor() as i64;
            while sign_after([lo[0] - s * a as Real, lo[1], lo[2]]) < 0 {
                a -= 1;
            }
            let mut b = ((hi[0] / s).floor() as i64).max(a);
            while sign_after([s * (b + 1) as Real - hi[0], -hi[1], -hi[2]]) < 0 {
                b += 1;
            }
            *c = [a, b];
        }
        let mut track = Track {
            level,
            cells,
            due: [[Real::INFINITY; 4]; 3],
            shift: None,
        };
        for k in 0..3 {
            self.certify_axis(m, &mut track, k, now);
        }
        track
    }

    /// `Some(s)` when the cells of `level`, a level above `own`, are `own`'s times `2^s`: an
    /// object living at `own` then covers, at `level`, the cells that hold its own cells (its
    /// box's ends cross a line of `level` only where they cross one of `own`), so its track
    /// there is derived from its own track instead of certified.
    pub(super) fn shift_to(&self, own: i32, level: i32) -> Option<u32> {
        if level == own {
            return None;
        }
        let r = self.cell_size(level) / self.cell_size(own);
        let s = r.log2().round();
        (r >= 1.0 && s <= 62.0 && (2.0 as Real).powi(s as i32) == r).then_some(s as u32)
    }

    /// The track of `m` at `level` above its own, at time `now`, given its own track `own`:
    /// derived from it where the cells allow, else certified.
    pub(super) fn track_at(&self, m: &Member, own: &Track, level: i32, now: Real) -> Track {
        match self.shift_to(m.level, level) {
            Some(s) => Track::derived(own, level, s),
            None => self.footprint(m, level, now),
        }
    }

    /// The four footprint certificates of `track` on `axis`.
    pub(super) fn certify_axis(&self, m: &Member, track: &mut Track, k: usize, now: Real) {
        let s = self.cell_size(track.level);
        let [a, b] = track.cells[k];
        let (lo, hi) = (m.lo[k].local(now), m.hi[k].local(now));
        let slack = |g: Real| HYSTERESIS * s + HYSTERESIS_ABS * g.abs();
        let (ga, gb) = (s * a as Real, s * (b + 1) as Real);
        let inner_a = s * (a + 1) as Real;
        let inner_b = s * b as Real;
        track.due[k] = [
            crossing(lo, ga, -1, now),
            if a < b {
                crossing(lo, inner_a + slack(inner_a), 1, now)
            } else {
                Real::INFINITY
            },
            crossing(hi, gb, 1, now),
            if a < b {
                crossing(hi, inner_b - slack(inner_b), -1, now)
            } else {
                Real::INFINITY
            },
        ];
    }

    fn next_crossing(m: &Member) -> Real {
        m.tracks
            .iter()
            .filter(|t| t.shift.is_none())
            .flat_map(|t| t.due.iter().flatten())
            .fold(Real::INFINITY, |x, &y| x.min(y))
    }

    pub(super) fn schedule_member(&mut self, id: u32) {
        let t = Self::next_crossing(self.member(id));
        if t.is_finite() {
            self.crossings_queue.schedule(id, t, 0);
        } else {
            self.crossings_queue.remove(id);
        }
    }

    /// Cells of `track` whose index on axis `k` is `i` (a slab), or all when `k` is 3.
    pub(super) fn cells_of(track: &Track, slab: Option<(usize, i64)>, out: &mut Vec<CellKey>) {
        out.clear();
        let range = |k: usize| match slab {
            Some((axis, i)) if axis == k => i..=i,
            _ => track.cells[k][0]..=track.cells[k][1],
        };
        for x in range(0) {
            for y in range(1) {
                for z in range(2) {
                    out.push((track.level, x, y, z));
                }
            }
        }
    }
}
