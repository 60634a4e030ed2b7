//! Levels and cell sizes: which level an object lives at, and how wide each level's cells are.

use super::{Grid, Member};
use super::{MAX_WIDEN, WIDEN_MIN_OBJECTS};
use crate::cell_math::{Ends, box_ends, box_width};
use kinetic_core::kds::{Bodies, ScalarKey};
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;

impl Grid {
    /// The side of level `level`'s cells: the level's nominal size, narrowed to the widest of
    /// the objects that first filled it and widened where they were sparse.
    pub(super) fn cell_size(&self, level: i32) -> Real {
        let own = self.base.unwrap_or(1.0) * self.ratio().powi(level);
        own * self.widen.get(&level).copied().unwrap_or(1.0)
    }

    /// Sizes the cells of the levels that `ids` are the first to occupy: first narrowed (by
    /// powers of two, down to the level below's) to the widest of those objects, so that a
    /// level holding only smaller objects than its nominal size does not draw every small
    /// object around into its cells; then, where the level's objects are sparse, widened to
    /// about one of them per cell over their centres' box (at most [`MAX_WIDEN`] times):
    /// fewer crossings, and still O(1) objects per cell.
    pub(super) fn widen_for(&mut self, ids: &[u32], bodies: &Bodies, now: Real) {
        let mut spread: FxHashMap<i32, (usize, Vec3, Vec3, Real)> = FxHashMap::default();
        for &id in ids {
            let width = box_width(bodies, id);
            let level = self.level_for(width);
            if self.occupied.contains(&level) || self.widen.contains_key(&level) {
                continue;
            }
            let c = bodies[id as usize]
                .as_ref()
                .expect("a live object")
                .plan
                .position_at(now);
            let e = spread.entry(level).or_insert((0, c, c, 0.0));
            *e = (e.0 + 1, e.1.min(c), e.2.max(c), e.3.max(width));
        }
        let min_f = 1.0 / self.ratio();
        for (level, (n, lo, hi, widest)) in spread {
            let nominal = self.cell_size(level);
            let mut f = 1.0;
            while f > min_f && nominal * f / 2.0 >= widest {
                f /= 2.0;
            }
            if n >= WIDEN_MIN_OBJECTS {
                let own = nominal * f;
                // The cells of side `c` over the centres' box, at least one a row on each
                // axis: a layer of objects (balls on a plane) or a line fills fewer than the
                // cube of its widest side.
                let cells = |c: Real| ((hi - lo) / c).max(Vec3::ONE).element_product();
                let mut g = 1.0;
                while g < MAX_WIDEN && cells(2.0 * g * own) >= n as Real {
                    g *= 2.0;
                }
                f *= g;
            }
            self.widen.insert(level, f);
        }
    }

    pub(super) fn ratio(&self) -> Real {
        if self.ratio >= 2.0 { self.ratio } else { 2.0 }
    }

    fn level_for(&self, width: Real) -> i32 {
        let base = self.base.unwrap_or(1.0);
        if width > 0.0 && width.is_finite() {
            (((width / base).log2() / self.ratio().log2()).ceil() as i32).clamp(-200, 200)
        } else {
            0
        }
    }

    pub(super) fn present(&self, id: u32) -> bool {
        self.members.get(id as usize).is_some_and(Option::is_some)
    }

    pub(super) fn member(&self, id: u32) -> &Member {
        self.members[id as usize].as_ref().expect("a member")
    }

    /// The member for object `id`'s current plan and box (no tracks yet).
    pub(super) fn make_member(&self, bodies: &Bodies, id: u32) -> Member {
        let (lo, hi): Ends = box_ends(bodies, id);
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        let width = (hi - lo).max_element();
        Member {
            level: self.level_for(width),
            width,
            lo: std::array::from_fn(|k| ScalarKey::from_plan(plan, k, lo[k])),
            hi: std::array::from_fn(|k| ScalarKey::from_plan(plan, k, hi[k])),
            tracks: Vec::new(),
            pairs: Default::default(),
            region: None,
        }
    }
}
