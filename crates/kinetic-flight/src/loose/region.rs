//! Regions: the box an object's box sweeps on its plan for a while, and when it leaves it.

use super::LooseGrid;
use crate::cell_math::{Local, box_ends, box_width, exit_from, swept_box};
use kinetic_core::kds::{Bodies, ScalarKey};
use kinetic_core::{Real, Vec3};

impl LooseGrid {
    /// Object `id`'s box ends on each axis as polynomials around `now`.
    pub(super) fn box_keys(bodies: &Bodies, id: u32, now: Real) -> [(Local, Local); 3] {
        let (lo, hi) = box_ends(bodies, id);
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        std::array::from_fn(|k| {
            (
                ScalarKey::from_plan(plan, k, lo[k]).local(now),
                ScalarKey::from_plan(plan, k, hi[k]).local(now),
            )
        })
    }

    /// A fresh region for object `id` at `now`: its corners. The region covers the box's
    /// sweep over a flight of `h` from `age h` before `now` (`age` in `[0, 1)`; 0 for a
    /// region from `now`), so that it ends `(1 - age) h` (and the margin) after `now`.
    pub(super) fn region(&self, bodies: &Bodies, id: u32, now: Real, age: Real) -> (Vec3, Vec3) {
        let w = box_width(bodies, id);
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        let (v, a) = (plan.velocity_at(now).length(), plan.acceleration.length());
        let d = self.travel * w;
        // The time to travel d: v h + a h^2 / 2 = d.
        let h = if a > 0.0 {
            (2.0 * d / (v + (v * v + 2.0 * a * d).sqrt())).max(0.0)
        } else if v > 0.0 {
            d / v
        } else {
            0.0
        }
        .max(self.least_flight)
        .min(self.horizon);
        let keys = Self::box_keys(bodies, id, now - age * h);
        // A margin of a few float spacings at least, so that a point object leaves after now.
        let scale = plan.position_at(now).abs().max_element() + w;
        let m = (self.margin * w.min(self.typical))
            .max(1e-9 * scale)
            .max(Real::MIN_POSITIVE);
        swept_box(&keys, h, m)
    }

    /// When object `id`'s box, on its plan, first leaves the region `lo..hi` after `now`
    /// (`now` if it is outside already or leaving).
    pub(super) fn exit_time(bodies: &Bodies, id: u32, lo: Vec3, hi: Vec3, now: Real) -> Real {
        exit_from(&Self::box_keys(bodies, id, now), lo, hi, now)
    }
}
